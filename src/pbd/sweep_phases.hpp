// The coloured solve's sweep, phase by phase (ColourSchedule): what a phase projects and the
// grains its chunks are cut to. Private to src/pbd (solver.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include "pbd/constraint_batches.hpp"

namespace shellcontract {
namespace sweep {

/// Smallest chunk a thread claims in the Coloured order (ColourSchedule). With 256, bear's
/// colours had about a dozen chunks for 16 threads, and its solve at 16 threads was slower than
/// with smaller grains (lab/history.md); bear x16's chunks are larger anyway (scale.md).
constexpr std::size_t COLOUR_GRAIN = 64;
/// COLOUR_GRAIN in batches of BATCH_LANES constraints.
constexpr std::size_t BATCH_GRAIN = COLOUR_GRAIN / BATCH_LANES;

/// Colour ranges of one constraint kind: constraint k of colour c lies in
/// [offsets[c], offsets[c + 1]). The Sequential order is one range over everything.
using ColourOffsets = std::vector<std::size_t>;

/// What a range of a sweep projects (ColourPhase::kind).
enum SweepKind : int {
  MEMBRANE_BATCHES,   ///< batches of membranes (Coloured order)
  MEMBRANES,          ///< membranes one by one
  ISOMETRIC_BATCHES,  ///< batches of isometric hinges (Coloured order)
  ISOMETRIC,          ///< isometric hinges one by one
  DIHEDRAL_BATCHES,   ///< batches of dihedral hinges (Coloured order)
  DIHEDRAL,           ///< dihedral hinges one by one
  ANISOTROPIC,
  PACK,    ///< vertices: positions and inverse masses into the batches' padded rows
  UNPACK,  ///< vertices: positions back from the padded rows
  /// Regional order (see REGIONS): items are parts; each runs all the membrane (hinge) batches
  /// of its part's interior, colour after colour.
  REGION_MEMBRANES,
  REGION_ISOMETRIC,
  /// Regional order: one item, all the interface membrane (hinge) batches, colour after colour.
  INTERFACE_MEMBRANES,
  INTERFACE_ISOMETRIC,
  ANISO_BATCHES,  ///< batches of anisotropic faces (Coloured order)
};

/// Vertices per chunk of a PACK or UNPACK phase.
constexpr std::size_t VERTEX_GRAIN = 1024;
/// Rows per task of the solve's copies into and out of the padded rows: large enough that the
/// tasks' overhead does not make the parallel copy slower than a serial one on a small mesh
/// (bench_projection's coloured membrane sweep; lab/history.md).
constexpr std::size_t COPY_GRAIN = 8192;

/// True for the kinds that work on the padded rows (PaddedVertex) instead of x.
inline bool padded_kind(int kind) {
  return kind == MEMBRANE_BATCHES || kind == ISOMETRIC_BATCHES || kind == DIHEDRAL_BATCHES ||
         kind == REGION_MEMBRANES || kind == REGION_ISOMETRIC || kind == INTERFACE_MEMBRANES ||
         kind == INTERFACE_ISOMETRIC || kind == ANISO_BATCHES;
}

}  // namespace sweep
}  // namespace shellcontract
