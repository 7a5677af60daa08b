// --delta auto and the bound on a given delta (sim/contact_distance.hpp).
#include "sim/contact_distance.hpp"

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <algorithm>

#include "collision/rest_gap.hpp"
#include "collision/self_collision/common.hpp"
#include "collision/topology.hpp"
#include "core/cancellation.hpp"
#include "core/plural.hpp"
#include "fem/triangle_element.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/rest_state.hpp"

namespace shellcontract {

double mean_edge_length(const Mesh& mesh) {
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto e : mesh.edges()) {
    sum += CGAL::Polygon_mesh_processing::edge_length(e, mesh);
    ++count;
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

namespace {

double edge_based_choice(double mean_edge, double cap) {
  const double share = AUTO_DELTA_PER_MEAN_EDGE * mean_edge;
  // A mesh without edges, or with edges of length 0 only, gives a share of 0: the cap keeps the
  // contact distance positive (the collision step needs delta > 0).
  return share > 0.0 ? std::min(cap, share) : cap;
}

/// At least this share of the vertices held at rest: nothing, or next to nothing, can move, and
/// the result would be the input with status ok; the warning says so first.
constexpr double MOSTLY_HELD_SHARE = 0.9;

bool mostly_held(const RestGapSurvey& s, std::size_t vertices) {
  return static_cast<double>(s.near_vertices) >= MOSTLY_HELD_SHARE * static_cast<double>(vertices);
}

std::string held_pairs_warning(const std::string& what, const RestGapSurvey& s, double delta,
                               std::size_t vertices) {
  const std::size_t pairs = s.near_pairs();
  const bool mostly = mostly_held(s, vertices);
  return (mostly ? "nothing can move (" + std::to_string(s.near_vertices) + " of the mesh's " +
                       counted(vertices, "vertex", "vertices") +
                       " are held: a flat or very thin shell), so the result would be the input: "
                 : std::string()) +
         "`delta` " + what + ": " + counted(pairs, "pair", "pairs") + " of primitives (" +
         std::to_string(s.near_vertex_face) + " vertex-face, " + std::to_string(s.near_edge_edge) +
         " edge-edge) " + one_or_many(pairs, "is", "are") + " closer than the contact distance " +
         shortest_text(delta) + " at rest (smallest gap " + shortest_text(s.smallest) +
         ", normalized units) without touching: the collision step holds their " +
         counted(s.near_vertices, "vertex", "vertices") +
         " at their rest positions while it finds such a pair in contact, step by step (not merely "
         "kept from crossing; motion around them may open a pair and free its vertices later)";
}

/// The pairs that a contact pushes apart beyond their rest gap: closer than the response's target
/// (RESPONSE_FACTOR delta) at rest, but not held (not closer than delta). Their first contact
/// sets them farther apart than they were made, and a thin shell whose two sheets are such pairs
/// swells under an outside pressure instead of contracting.
std::string pushed_apart_warning(const std::string& what, const RestGapSurvey& s, double delta,
                                 const std::string& remedy) {
  const std::size_t pairs = s.near_pairs();
  return "`delta` " + what + ": " + counted(pairs, "pair", "pairs") + " of primitives (" +
         std::to_string(s.near_vertex_face) + " vertex-face, " + std::to_string(s.near_edge_edge) +
         " edge-edge) " + one_or_many(pairs, "lies", "lie") + " between the contact distance " +
         shortest_text(delta) + " and twice it at rest (smallest gap " + shortest_text(s.smallest) +
         ", normalized units): the collision response pushes a pair in contact to " +
         shortest_text(collision_pipeline::RESPONSE_FACTOR * delta) +
         ", beyond their rest gap, and a thin shell can swell instead of contracting; " + remedy;
}

/// Whether every touching vertex the survey found is a corner of a zero-area face: a vertex on
/// another face's edge because a face between them has no area (a sliver left by a modeller), not
/// two parts or sheets in contact. Only a complete sample can tell (touching_sample keeps a few).
bool touching_only_at_zero_area_faces(const Mesh& mesh, const RestGapSurvey& s) {
  if (s.touching_vertices == 0 || s.touching_vertices > s.touching_sample.size()) return false;
  std::vector<char> corner(mesh.number_of_vertices(), 0);
  const auto at = [&](VertexIndex v) {
    const Point3& p = mesh.point(v);
    return Vec3(p.x(), p.y(), p.z());
  };
  for (const auto f : mesh.faces()) {
    const HalfedgeIndex h = mesh.halfedge(f);
    const VertexIndex a = mesh.target(h), b = mesh.target(mesh.next(h)),
                      c = mesh.target(mesh.next(mesh.next(h)));
    // The rest state's rule (rest_state.cpp): such a face carries no membrane energy.
    if (triangle_rest(at(a), at(b), at(c)).degenerate)
      for (const VertexIndex v : {a, b, c}) corner[v.idx()] = 1;
  }
  return std::all_of(s.touching_sample.begin(), s.touching_sample.end(),
                     [&](int v) { return corner[static_cast<std::size_t>(v)] != 0; });
}

/// The pairs that touch at rest: the collision step excludes them for the whole run (RestPairs:
/// no response can keep a pair of distance 0 on a side it does not have), so parts pressed
/// together there pass through each other, and `check --against` and `--validate` count no
/// crossing of faces that already touched in the input. The vertices are named as the input
/// numbers them (a welded vertex by its first copy). Where they are all corners of zero-area
/// faces the advice on parts does not apply and is not given.
std::string touching_pairs_warning(const Mesh& mesh, const RestGapSurvey& s, double delta) {
  const std::size_t pairs = s.touching_pairs();
  const bool at_zero_area = touching_only_at_zero_area_faces(mesh, s);
  std::vector<std::size_t> names(s.touching_sample.begin(), s.touching_sample.end());
  if (has_welded_seams(mesh)) {
    const std::vector<std::size_t> map = input_vertex_map(mesh);
    for (std::size_t& v : names)
      v = static_cast<std::size_t>(std::find(map.begin(), map.end(), v) - map.begin());
  }
  std::string listed;
  for (std::size_t i = 0; i < names.size(); ++i)
    listed += (i ? ", " : "") + std::to_string(names[i]);
  if (s.touching_vertices > names.size()) listed += ", ...";
  const std::string counted_pairs =
      counted(pairs, "pair", "pairs") + " of primitives (" +
      std::to_string(s.touching_vertex_face) + " vertex-face, " +
      std::to_string(s.touching_edge_edge) + " edge-edge) " +
      one_or_many(pairs, "touches", "touch") + " at rest, at or next to " +
      counted(s.touching_vertices, "vertex", "vertices") + " (" + listed + ")";
  if (at_zero_area)
    return counted_pairs +
           ", each a corner of a zero-area face (named with the input's checks): a vertex lying "
           "on another face's edge. The collision step leaves those pairs out for the whole run "
           "(a pair at distance 0 has no side to keep), so the surface is not kept from passing "
           "through itself right there; removing the zero-area face from the input (merging its "
           "corner into the edge it lies on) makes them ordinary neighbours";
  return counted_pairs +
         ": parts in contact, a surface that touches itself, or a zero-area face. The collision "
         "step cannot keep a touching pair on its sides and leaves it out for the whole run, so "
         "the parts can pass through each other there (`check --against` and `--validate` do not "
         "count it: those faces already touch in the input). Separate the parts by at least the "
         "contact distance " +
         shortest_text(delta) +
         " (normalized units: a share of the bounding-box diagonal), or join them into one "
         "surface if they are one part";
}

}  // namespace

double auto_contact_distance(const Mesh& mesh, double cap) {
  return edge_based_choice(mean_edge_length(mesh), cap);
}

ContactDistanceChoice choose_contact_distance(const Mesh& mesh, const SimOptions& options) {
  ContactDistanceChoice out;
  const double mean_edge = mean_edge_length(mesh);
  const double by_edge = edge_based_choice(mean_edge, options.collision.delta);
  // The default is never refused: a mesh fine enough for it to exceed the share ran with it
  // before the bound existed, and its pairs held at rest, if any, are named below.
  const double bound = std::max(MAX_DELTA_PER_MEAN_EDGE * mean_edge, CollisionOptions{}.delta);
  if (!options.auto_delta && options.collision.delta > bound)
    throw UsageError(
        "`delta` " + shortest_text(options.collision.delta) + " is above this mesh's bound " +
        shortest_text(bound) + " (1/" + shortest_text(1.0 / MAX_DELTA_PER_MEAN_EDGE) +
        " of its mean edge, normalized units, or the default if larger): pairs that "
        "are not neighbours would be in contact at rest and pushed into each "
        "other, and the shell would swell; `delta` auto would choose " +
        shortest_text(by_edge) + " (or less where parts are closer than that at rest)");
  out.delta = options.auto_delta ? by_edge : options.collision.delta;
  // A run's cancel (core/cancellation.hpp) between the passes, each long on a large mesh; the
  // surveys also ask between chunks of their pairs (their broad phase is one call, heard at its
  // end).
  cancellation_point();
  const CollisionTopology topo =
      make_collision_topology(faces_array(mesh), static_cast<int>(mesh.number_of_vertices()));
  cancellation_point();
  const Positions rest = positions_from_mesh(mesh);
  const double response = collision_pipeline::RESPONSE_FACTOR;
  const BroadPhaseMethod method = options.collision.method;
  // The pairs a contact would push beyond their rest gap (held ones aside), named whatever delta.
  auto warn_pushed_apart = [&](const std::string& what, const std::string& remedy) {
    const RestGapSurvey band =
        survey_rest_gaps(topo, rest, response * out.delta, method, out.delta);
    if (band.near_pairs() > 0)
      out.warnings.push_back(pushed_apart_warning(what, band, out.delta, remedy));
  };
  // Every survey counts the touching pairs (distance 0 is within any reach); named first, with
  // the delta chosen, as the most serious thing said here.
  auto warn_touching = [&](const RestGapSurvey& survey) {
    if (survey.touching_pairs() > 0)
      out.warnings.insert(out.warnings.begin(), touching_pairs_warning(mesh, survey, out.delta));
  };
  if (!options.auto_delta) {
    const RestGapSurvey survey = survey_rest_gaps(topo, rest, out.delta, method);
    warn_touching(survey);
    out.held_at_rest = mostly_held(survey, mesh.number_of_vertices());
    if (survey.near_pairs() > 0)
      out.warnings.push_back(held_pairs_warning(shortest_text(out.delta), survey, out.delta,
                                                mesh.number_of_vertices()) +
                             "; `delta` auto or a delta below the smallest gap lets them move");
    warn_pushed_apart(
        shortest_text(out.delta),
        "`delta` auto or a delta below half the smallest gap keeps the contacts within the rest "
        "gaps");
    return out;
  }
  // Auto surveys as far as the response pushes: half the smallest gap within that reach leaves
  // every pair out of contact at rest and lets no contact push a pair beyond its rest gap.
  RestGapSurvey survey = survey_rest_gaps(topo, rest, response * out.delta, method);
  const RestGapSurvey first = survey;
  if (survey.near_pairs() == 0) {
    warn_touching(first);
    return out;
  }
  const double floor = AUTO_DELTA_FLOOR_SHARE * by_edge;
  out.delta = std::min(out.delta, std::max(floor, AUTO_DELTA_PER_REST_GAP * survey.smallest));
  if (out.delta > floor) {
    warn_touching(first);
    return out;
  }
  survey = survey_rest_gaps(topo, rest, out.delta, method);
  out.held_at_rest = mostly_held(survey, mesh.number_of_vertices());
  const std::string lowest = "auto goes no lower: a smaller gap is a near-degenerate input";
  if (survey.near_pairs() > 0)
    out.warnings.push_back(
        held_pairs_warning("auto", survey, out.delta, mesh.number_of_vertices()) + " (" + lowest +
        ")");
  warn_pushed_apart("auto", lowest);
  warn_touching(first);
  return out;
}

}  // namespace shellcontract
