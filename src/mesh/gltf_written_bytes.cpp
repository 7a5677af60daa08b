// The glTF document's check that the bytes it rewrites are read as nothing else
// (gltf_written_bytes.hpp).
#include "mesh/gltf_written_bytes.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <utility>

#include "shellcontract/error.hpp"

namespace shellcontract::gltf {

void check_written_bytes_alone(const std::string& path, const tinygltf::Model& model,
                               const GltfSoup& soup, const std::vector<Written>& positions,
                               const std::vector<Written>& normals) {
  const auto primitive = [&](std::size_t d) -> const tinygltf::Primitive& {
    return model.meshes[soup.drawn[d].mesh].primitives[soup.drawn[d].primitive];
  };
  const auto name = [&](std::size_t d) {
    return "mesh " + std::to_string(soup.drawn[d].mesh) + " primitive " +
           std::to_string(soup.drawn[d].primitive);
  };
  const auto refuse = [&](const std::string& what) {
    throw InputError(path + ": not writable with new positions: " + what);
  };
  std::map<int, std::size_t> position_of;  // a POSITION accessor, the first primitive drawing it
  for (std::size_t d = 0; d < positions.size(); ++d) position_of.emplace(positions[d].accessor, d);
  for (std::size_t d = 0; d < normals.size(); ++d) {
    const auto it = position_of.find(normals[d].accessor);
    if (it != position_of.end())
      refuse(name(d) + " NORMAL and " + name(it->second) + " POSITION share accessor " +
             std::to_string(it->first));
  }
  struct Span {
    std::size_t buffer, begin, end;
    bool normal;
    std::size_t drawn;
  };
  std::vector<Span> spans;
  std::set<int> done;
  for (std::size_t d = 0; d < positions.size(); ++d)
    for (const Written* w : {&positions[d], &normals[d]}) {
      if (w->accessor < 0 || !done.insert(w->accessor).second) continue;
      for (std::size_t e = 0; e < w->view.count; ++e) {
        const std::size_t at = w->view.offset + e * w->view.stride;
        spans.push_back({w->view.buffer, at, at + 12, w == &normals[d], d});
      }
    }
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) {
    return std::tie(a.buffer, a.begin, a.normal) < std::tie(b.buffer, b.begin, b.normal);
  });
  const auto shared = [&](const std::string& what, const Span& s, std::size_t at) {
    const Written& w = s.normal ? normals[s.drawn] : positions[s.drawn];
    refuse(what + " shares bytes with " + name(s.drawn) + (s.normal ? " NORMAL" : " POSITION") +
           " (accessor " + std::to_string(w.accessor) + "; buffer " + std::to_string(s.buffer) +
           " byte " + std::to_string(at) + ")");
  };
  // Each span against the furthest-reaching earlier span of the other kind in its buffer.
  const Span* reach[2] = {nullptr, nullptr};
  for (const Span& s : spans) {
    for (const Span*& r : reach)
      if (r && r->buffer != s.buffer) r = nullptr;
    if (const Span* other = reach[!s.normal]; other && other->end > s.begin) {
      const Written& w = s.normal ? normals[s.drawn] : positions[s.drawn];
      shared(name(s.drawn) + (s.normal ? " NORMAL" : " POSITION") + " (accessor " +
                 std::to_string(w.accessor) + ")",
             *other, s.begin);
    }
    const Span*& mine = reach[s.normal];
    if (!mine || s.end > mine->end) mine = &s;
  }
  // The first span that bytes [begin, end) of `buffer` meet: spans are 12 bytes, so only one
  // starting at most 11 bytes before `begin` can reach it.
  const auto meets = [&](std::size_t buffer, std::size_t begin, std::size_t end) -> const Span* {
    const std::pair<std::size_t, std::size_t> from{buffer, begin < 11 ? 0 : begin - 11};
    auto it = std::lower_bound(spans.begin(), spans.end(), from, [](const Span& a, const auto& k) {
      return std::tie(a.buffer, a.begin) < std::tie(k.first, k.second);
    });
    for (; it != spans.end() && it->buffer == buffer && it->begin < end; ++it)
      if (it->end > begin) return &*it;
    return nullptr;
  };
  // Every other accessor a drawn primitive reads, element by element where its extent meets a
  // span (an interleaved buffer view).
  std::set<int> checked;
  for (std::size_t d = 0; d < soup.drawn.size(); ++d) {
    const tinygltf::Primitive& p = primitive(d);
    std::vector<std::pair<std::string, int>> read = {{"indices", p.indices}};
    for (const auto& [key, a] : p.attributes)
      if (key != "POSITION" && (key != "NORMAL" || normals[d].accessor < 0))
        read.push_back({key, a});
    for (std::size_t t = 0; t < p.targets.size(); ++t)
      for (const auto& [key, a] : p.targets[t])
        read.push_back({"morph target " + std::to_string(t) + " " + key, a});
    for (const auto& [key, a] : read) {
      if (a < 0 || static_cast<std::size_t>(a) >= model.accessors.size() ||
          !checked.insert(a).second)
        continue;
      const tinygltf::Accessor& acc = model.accessors[static_cast<std::size_t>(a)];
      const int size =
          tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(acc.componentType)) *
          tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
      if (size <= 0 || acc.sparse.isSparse || acc.count == 0) continue;
      const auto n = static_cast<std::size_t>(size);
      gltf::ElementView v;
      try {
        v = element_view(path, model, a, key, n);
      } catch (const InputError&) {
        continue;  // not read by the document, so not refused for it
      }
      if (!meets(v.buffer, v.offset, v.offset + (v.count - 1) * v.stride + n)) continue;
      for (std::size_t e = 0; e < v.count; ++e) {
        const std::size_t at = v.offset + e * v.stride;
        if (const Span* s = meets(v.buffer, at, at + n))
          shared(name(d) + " " + key + " (accessor " + std::to_string(a) + ")", *s,
                 std::max(at, s->begin));
      }
    }
  }
}
}  // namespace shellcontract::gltf
