// Private to the region finder: growing a geodesic disc from a seed while a sphere fits it
// (step 2 of the algorithm in region_selection.hpp).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "geometry/cap_internal.hpp"
#include "geometry/curvature.hpp"

namespace shellcontract::detail {

/// What the growth reads of a vertex, packed so that one visit touches one record: its
/// position, its area (a third of the incident faces) and that area again where the smoothed
/// curvature is concave (0 elsewhere).
struct GrowthVertex {
  Vec3 point = Vec3::Zero();
  double area = 0.0, concave_area = 0.0;
};

std::vector<GrowthVertex> growth_vertices(const MeshArrays& m, const Positions& x, const Eigen::VectorXd& concave_field);

/// The mesh as the growth walks it, its vertices renumbered ("slots") along a space-filling
/// curve through their positions: a disc's records then lie close together in memory, where
/// the mesh's own order (a subdivided mesh appends each level's midpoints) scatters a disc's
/// neighbours over the whole array and every visit misses the cache. Only the memory layout
/// changes: the growth still orders its vertices by (distance, mesh index), so every disc is
/// the same as in the mesh's order. Built once, shared by the growers of all threads.
class GrowthGraph {
 public:
  GrowthGraph(const MeshArrays& m, const std::vector<GrowthVertex>& vertices);

  /// A neighbour of a slot: its slot, its mesh index and the edge's length.
  struct Neighbour {
    double len;
    int slot, id;
  };

  std::size_t size() const { return vertex_.size(); }
  int slot(int id) const { return slot_[static_cast<std::size_t>(id)]; }
  int id(int slot) const { return id_[static_cast<std::size_t>(slot)]; }
  const GrowthVertex& vertex(int slot) const { return vertex_[static_cast<std::size_t>(slot)]; }
  const Neighbour* nbr_begin(int slot) const { return nbr_.data() + nbr_start_[static_cast<std::size_t>(slot)]; }
  const Neighbour* nbr_end(int slot) const { return nbr_.data() + nbr_start_[static_cast<std::size_t>(slot) + 1]; }
  /// Faces are renumbered too (face slots, in the order of their smallest corner slot): a
  /// face's corners (vertex slots, in the mesh's corner order) and its neighbours across its
  /// edges (face slots, -1 on a border).
  struct Face {
    std::array<int, 3> corner, nbr;
  };
  /// The face slots around a vertex slot, in the mesh's order.
  const int* faces_begin(int slot) const { return face_.data() + face_start_[static_cast<std::size_t>(slot)]; }
  const int* faces_end(int slot) const { return face_.data() + face_start_[static_cast<std::size_t>(slot) + 1]; }
  const Face& face(int face_slot) const { return face_rec_[static_cast<std::size_t>(face_slot)]; }
  int face_id(int face_slot) const { return face_id_[static_cast<std::size_t>(face_slot)]; }

 private:
  std::vector<int> slot_, id_, face_id_;
  std::vector<GrowthVertex> vertex_;
  std::vector<int> nbr_start_, face_start_, face_;
  std::vector<Neighbour> nbr_;
  std::vector<Face> face_rec_;
};

/// Grows discs from seeds. Scratch arrays are kept between seeds (reset through the lists of
/// what a growth touched), so a growth costs what it visits, not the mesh's size; one grower
/// per thread.
class CapGrower {
 public:
  /// With a graph shared between growers (it must outlive the grower).
  CapGrower(const MeshArrays& m, const GrowthGraph& graph, const CurvatureField& c, const RegionOptions& o);
  /// With a graph of its own.
  CapGrower(const MeshArrays& m, const std::vector<GrowthVertex>& vertices, const CurvatureField& c,
            const RegionOptions& o);

  /// The cap around `seed`, not entering vertices with (*blocked)[v] != 0 (none when blocked
  /// is null). Nothing when no disc passed the tests. The cap's faces are listed only when
  /// want_faces is null or true of the cap (the free growth's flat caps are only counted, and
  /// listing a disc's faces costs as much as growing it).
  std::optional<Cap> grow(int seed, const std::vector<char>* blocked,
                          const std::function<bool(const Cap&)>* want_faces = nullptr);

  /// For --region-at (select_regions_at): the largest cap around `seed` that passes grow's tests
  /// and whose region is within max_area_fraction of the total area, its faces listed;
  /// region_area(faces) is the area of the region the caller makes of a disc's faces. Instead of
  /// stopping where the popped vertices' area passes the bound (grow's test, which lets the
  /// last disc's faces overshoot it), the growth stops once the disc's own faces exceed it.
  /// Nothing when no such cap passed the tests.
  std::optional<Cap> grow_within(int seed, const std::vector<char>* blocked,
                                 const std::function<double(const std::vector<int>&)>& region_area);

 private:
  struct State {
    double dist;
    bool popped;
  };
  /// A heap entry: tentative distance, mesh index (the tie-break, as in the mesh's order), slot.
  struct Entry {
    double dist;
    int id, slot;
  };
  /// A 4-ary min-heap of entries on (distance, mesh index). An entry is kept as one 128-bit
  /// key: the distance's bits (distances are >= 0 and finite, so their bit patterns order as
  /// the numbers do), the mesh index, the slot; no two entries tie on the first two, so the
  /// key orders as (distance, mesh index) and any heap pops the same sequence. Its sift-down
  /// picks the least child by comparing keys without branches (std::pop_heap's binary sift
  /// mispredicts about one branch per level, and the growth pops millions of entries).
  class EntryHeap {
   public:
    __extension__ typedef unsigned __int128 Key;
    bool empty() const { return h_.empty(); }
    void clear() { h_.clear(); }
    void push(const Entry& e);
    Entry pop();

   private:
    std::vector<Key> h_;
  };
  /// The growth both share: the last disc that passed (sphere, rho; no faces). grow (passes
  /// null) stops where the popped vertices' area passes max_area_fraction and sets *unbounded;
  /// grow_within (passes given) records every disc that passed, in growing order, and stops
  /// once the disc's faces exceed the bound.
  std::optional<Cap> grow_disc(int seed, const std::vector<char>* blocked, std::vector<Cap>* passes,
                               bool* unbounded);
  std::vector<int> disc_faces(int seed_slot, double rho, const std::vector<char>* blocked);
  void reset();

  const MeshArrays& m_;
  std::unique_ptr<const GrowthGraph> own_;
  const GrowthGraph& g_;
  const CurvatureField& c_;
  const RegionOptions& o_;
  std::vector<State> state_;  ///< by slot
  std::vector<char> in_, keep_;  ///< per face slot, all 0 between calls
  std::vector<int> touched_;     ///< slots
  EntryHeap heap_;
};

}  // namespace shellcontract::detail
