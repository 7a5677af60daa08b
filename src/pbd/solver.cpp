#include "pbd/solver.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "bending/isometric_bending.hpp"
#include "core/arena_threads.hpp"
#include "material/stvk.hpp"
#include "pbd/aniso_frames.hpp"
#include "pbd/colour_schedule.hpp"
#include "pbd/colouring.hpp"
#include "pbd/constraint_batches.hpp"
#include "pbd/constraint_kernels.hpp"
#include "pbd/membrane_energy.hpp"
#include "pbd/regional_order.hpp"
#include "pbd/rest_slots.hpp"
#include "pbd/sweep_phases.hpp"

namespace shellcontract {
namespace {

// The regional order's layout (regional_order.hpp).
using regional::breadth_first_rows;
using regional::interface_count;
using regional::MAX_INTERFACE_FRACTION;
using regional::REGION_GROUPS;
using regional::regional_in_place;
using regional::REGIONS;
using regional::renamed;
using regional::sort_colours_by_row;
using regional::split_vertices;
using solver_energies::add_face_energies;
using solver_energies::membrane_energy;
using namespace sweep;  // NOLINT(google-build-using-namespace): the sweep's phase kinds

using aniso_frames::row;

/// The solver for one concrete membrane material M and anisotropic energy A: the template makes
/// the per-element material calls direct and inlinable (material.hpp).
template <class M, class A>
class GaussSeidelSolver final : public ConstraintSolver {
 public:
  GaussSeidelSolver(M material, A aniso, double energy_floor, ConstraintSet set,
                    const SolverSettings& settings, Faces faces)
      : material_(std::move(material)),
        aniso_(std::move(aniso)),
        set_(std::move(set)),
        settings_(settings),
        faces_(std::move(faces)),
        energy_floor_(energy_floor) {
    set_.anisotropic_k_a.resize(set_.anisotropic.size(), 0.0);
    coloured_ = settings_.order == ConstraintOrder::Coloured;
    if (coloured_) {
      // Reorder every per-constraint array by colour once; the sweep then reads them in order.
      membrane_colours_ = colour_in_place(set_.membranes);
      isometric_colours_ = colour_in_place(set_.isometric_hinges);
      dihedral_colours_ = colour_in_place(set_.dihedral_hinges);
      const Colouring aniso = colour_constraints(set_.anisotropic);
      apply_order(set_.anisotropic, aniso.order);
      apply_order(set_.anisotropic_k_a, aniso.order);
      aniso_colours_ = aniso.offsets;
      membrane_num_colours_ = static_cast<int>(membrane_colours_.size()) - 1;
      isometric_num_colours_ = static_cast<int>(isometric_colours_.size()) - 1;
      // The regional order needs every constraint of the sweep in a batched kind (one padded
      // state for the whole sweep). Not extended to the dihedral hinges, though they have
      // batches: its REGIONS parts are fixed at two whatever the thread count (for bit-identical
      // results), so the default bending's solve would use at most two cores on a many-core
      // machine (as the isometric hinges' does), where it now runs one phase per colour on all
      // of them (lab/pages/scale.md, "The dihedral hinges in batches").
      regional_ = BatchedMembraneProjection<M>::value && !set_.membranes.empty() &&
                  set_.dihedral_hinges.empty() && set_.anisotropic.empty();
      const int num_vertices = vertex_count(set_);
      // Padded rows in breadth-first order; the parts are cut in that order.
      row_vertex_ = breadth_first_rows(set_.membranes, num_vertices);
      vertex_row_.resize(row_vertex_.size());
      for (std::size_t k = 0; k < row_vertex_.size(); ++k)
        vertex_row_[static_cast<std::size_t>(row_vertex_[k])] = static_cast<int>(k);
      // Each colour in row order: a thread's chunk of a colour then reads and writes a part of
      // the rows of its own, as it does in the regional layout, and the colour's loads run
      // forward. The same bits, and a faster solve at one and two threads (lab/pages/scale.md,
      // "The dihedral hinges in batches").
      sort_colours_by_row(set_.membranes, membrane_colours_, vertex_row_);
      sort_colours_by_row(set_.isometric_hinges, isometric_colours_, vertex_row_);
      sort_colours_by_row(set_.dihedral_hinges, dihedral_colours_, vertex_row_);
      const std::vector<std::uint8_t> row_part =
          split_vertices(num_vertices, renamed(set_.membranes, vertex_row_),
                         renamed(set_.isometric_hinges, vertex_row_));
      std::vector<std::uint8_t> part(row_part.size());  // by vertex id
      for (std::size_t v = 0; v < part.size(); ++v)
        part[v] = row_part[static_cast<std::size_t>(vertex_row_[v])];
      auto few = [&](const auto& records) {
        return static_cast<double>(interface_count(records, part)) <=
               MAX_INTERFACE_FRACTION * static_cast<double>(records.size());
      };
      regional_ = regional_ && few(set_.membranes) && few(set_.isometric_hinges);
      if (regional_) {
        membrane_colours_ = regional_in_place(set_.membranes, membrane_colours_, part);
        isometric_colours_ = regional_in_place(set_.isometric_hinges, isometric_colours_, part);
      }
      arena_ = run_arena(settings_.threads);
    } else {
      membrane_colours_ = {0, set_.membranes.size()};
      isometric_colours_ = {0, set_.isometric_hinges.size()};
      dihedral_colours_ = {0, set_.dihedral_hinges.size()};
      aniso_colours_ = {0, set_.anisotropic.size()};
    }
    packed_membranes_.reserve(set_.membranes.size());
    for (const MembraneConstraint& c : set_.membranes) packed_membranes_.push_back(pack_membrane(c));
    if (coloured_) {
      // Coloured order: the membranes of a material with a batched projection (every
      // MaterialKind), the isometric and dihedral hinges and the anisotropic faces are projected
      // four per SIMD batch (constraint_batches.hpp); the batches address padded rows.
      if constexpr (BatchedMembraneProjection<M>::value)
        membrane_batches_ =
            make_membrane_batches(renamed(packed_membranes_, vertex_row_), membrane_colours_);
      isometric_batches_ =
          make_isometric_batches(renamed(set_.isometric_hinges, vertex_row_), isometric_colours_);
      dihedral_batches_ =
          make_dihedral_batches(renamed(set_.dihedral_hinges, vertex_row_), dihedral_colours_);
      // From here the batches hold the membranes' rest data: the packed copy would only add to
      // the run's peak, which the dihedral batches had already raised (lab/history.md).
      if (!membrane_batches_.batches.empty()) std::vector<PackedMembrane>().swap(packed_membranes_);
    }
    packed_aniso_.reserve(set_.anisotropic.size());
    aniso_data_.reserve(set_.anisotropic.size());
    for (const MembraneConstraint& c : set_.anisotropic) {
      packed_aniso_.push_back(pack_membrane(c));
      aniso_data_.push_back(c.data);
    }
    if constexpr (BatchedAnisoProjection<A>::value)
      if (coloured_ && !set_.anisotropic.empty()) make_aniso_layout();
    if (settings_.kind == SolverKind::Xpbd) {
      // Batched kinds keep BATCH_LANES multipliers per batch, padding lanes included.
      lambda_membrane_.resize(std::max(set_.membranes.size(),
                                       BATCH_LANES * membrane_batches_.batches.size()));
      lambda_isometric_.resize(3 * std::max(set_.isometric_hinges.size(),
                                            BATCH_LANES * isometric_batches_.batches.size()));
      lambda_dihedral_.resize(std::max(set_.dihedral_hinges.size(),
                                       BATCH_LANES * dihedral_batches_.batches.size()));
      lambda_aniso_.resize(std::max(set_.anisotropic.size(),
                                    BATCH_LANES * aniso_batches_.batches.size()));
    }
    aniso_normal_.resize(set_.anisotropic.size(), Vec3::Zero());
    aniso_orientation_.resize(set_.anisotropic.size(), 1.0);
    rest_slots_ = MembraneRestSlots(set_.membranes, membrane_colours_);
    hinge_slots_ = HingeRestSlots(dihedral_colours_);
  }

  bool set_membrane_rest(int face, const Mat2& Dm_inv, double rest_area) override {
    return rest_slots_.set(face, Dm_inv, rest_area, set_.membranes, packed_membranes_,
                           membrane_batches_);
  }
  void set_dihedral_rest_angle(std::size_t record, double rest_angle) override {
    hinge_slots_.set_angle(record, rest_angle, set_.dihedral_hinges, dihedral_batches_);
  }

  void solve(Positions& x, const Eigen::VectorXd& inv_mass) override {
    if (coloured_)
      arena_->arena().execute([&] { solve_impl(x, inv_mass); });
    else
      solve_impl(x, inv_mass);
  }

  ColourCounts colour_counts() const override {
    ColourCounts n;
    if (!coloured_) return n;
    n.membrane = membrane_num_colours_;
    n.isometric = isometric_num_colours_;
    n.regional = regional_;
    n.dihedral = static_cast<int>(dihedral_colours_.size()) - 1;
    n.anisotropic = static_cast<int>(aniso_colours_.size()) - 1;
    return n;
  }

  ConstraintEnergies energies(const Positions& x) const override {
    ConstraintEnergies e;
    e.membrane = membrane_energy(material_, set_.membranes, x, nullptr);
    e.anisotropic = membrane_energy(aniso_, set_.anisotropic, x, &aniso_orientation_);
    for (const IsometricHingeConstraint& c : set_.isometric_hinges) {
      const Vec3 h = c.K(0) * row(x, c.v[0]) + c.K(1) * row(x, c.v[1]) + c.K(2) * row(x, c.v[2]) +
                     c.K(3) * row(x, c.v[3]);
      e.bending += settings_.k_bending * 0.5 * c.three_over_area * h.squaredNorm();
    }
    for (const DihedralHingeConstraint& c : set_.dihedral_hinges)
      e.bending += dihedral_bending_energy(c.rest, settings_.k_bending, row(x, c.v[0]),
                                           row(x, c.v[1]), row(x, c.v[2]), row(x, c.v[3]));
    return e;
  }

  const ConstraintSet& constraints() const override { return set_; }

  Eigen::VectorXd face_energies(const Positions& x, Eigen::Index num_faces) const override {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(num_faces);
    add_face_energies(material_, set_.membranes, x, nullptr, e);
    add_face_energies(aniso_, set_.anisotropic, x, &aniso_orientation_, e);
    return e;
  }

 private:
  template <class Record>
  static ColourOffsets colour_in_place(std::vector<Record>& records) {
    Colouring c = colour_constraints(records);
    apply_order(records, c.order);
    return std::move(c.offsets);
  }

  /// Phases of one sweep in math-spec 9.4 order (membranes, isometric hinges, dihedral hinges,
  /// anisotropic faces), one per colour, each kind through its batches when it has them, with a
  /// PACK or UNPACK phase wherever the sweep moves between x and the padded rows. A sweep starts
  /// in the state its last phase leaves (solve_impl packs before the first sweep and unpacks
  /// after the last one as needed).
  std::vector<ColourPhase> sweep_phases(std::size_t num_vertices) const {
    if (regional_) {
      // Membranes, then hinges (math-spec 9.4): the parts' interiors in parallel, then the
      // interface. Every kind here works on the padded rows: no PACK or UNPACK inside a sweep.
      std::vector<ColourPhase> phases;
      if (!set_.membranes.empty()) {
        phases.push_back({REGION_MEMBRANES, 0, REGIONS, 1});
        phases.push_back({INTERFACE_MEMBRANES, 0, 1, 1});
      }
      if (!set_.isometric_hinges.empty()) {
        phases.push_back({REGION_ISOMETRIC, 0, REGIONS, 1});
        phases.push_back({INTERFACE_ISOMETRIC, 0, 1, 1});
      }
      return phases;
    }
    std::vector<ColourPhase> phases;
    auto add = [&](SweepKind kind, const ColourOffsets& colours, std::size_t grain) {
      for (std::size_t c = 0; c + 1 < colours.size(); ++c)
        if (colours[c + 1] > colours[c]) phases.push_back({kind, colours[c], colours[c + 1], grain});
    };
    if (!membrane_batches_.batches.empty())
      add(MEMBRANE_BATCHES, membrane_batches_.offsets, BATCH_GRAIN);
    else
      add(MEMBRANES, membrane_colours_, COLOUR_GRAIN);
    if (!isometric_batches_.batches.empty())
      add(ISOMETRIC_BATCHES, isometric_batches_.offsets, BATCH_GRAIN);
    else
      add(ISOMETRIC, isometric_colours_, COLOUR_GRAIN);
    if (!dihedral_batches_.batches.empty())
      add(DIHEDRAL_BATCHES, dihedral_batches_.offsets, BATCH_GRAIN);
    else
      add(DIHEDRAL, dihedral_colours_, COLOUR_GRAIN);
    if (!aniso_batches_.batches.empty())
      add(ANISO_BATCHES, aniso_batches_.offsets, BATCH_GRAIN);
    else
      add(ANISOTROPIC, aniso_colours_, COLOUR_GRAIN);
    std::vector<ColourPhase> out;
    for (std::size_t p = 0; p < phases.size(); ++p) {
      // The state before phase p: the previous phase's, or (p = 0) the last phase's.
      const bool before = padded_kind(phases[p == 0 ? phases.size() - 1 : p - 1].kind);
      const bool now = padded_kind(phases[p].kind);
      if (p > 0 && before != now) out.push_back({now ? PACK : UNPACK, 0, num_vertices, VERTEX_GRAIN});
      out.push_back(phases[p]);
    }
    // Back to the state the first phase expects, for the next sweep.
    if (!phases.empty() && padded_kind(phases.front().kind) != padded_kind(phases.back().kind))
      out.push_back({padded_kind(phases.front().kind) ? PACK : UNPACK, 0, num_vertices, VERTEX_GRAIN});
    return out;
  }

  /// Projects items [b, e) of one kind in order (constraints, or batches of four).
  void project_range(int kind, std::size_t b, std::size_t e, const ProjectionContext& ctx) {
    PaddedVertex* const xw = padded_.data();
    const bool xpbd = settings_.kind == SolverKind::Xpbd;
    const double kb = settings_.k_bending;
    const ElementMaterialData isotropic{};  // isotropic membranes ignore the fibre
    // The xpbd tests are outside the inner loops so each loop body is branch-free.
    switch (kind) {
      case MEMBRANE_BATCHES:
        if constexpr (BatchedMembraneProjection<M>::value)
          BatchedMembraneProjection<M>::project(material_, &membrane_batches_.batches[b], e - b, xw, ctx,
                                                xpbd ? &lambda_membrane_[BATCH_LANES * b] : nullptr);
        break;
      case MEMBRANES:
        if (xpbd)
          for (std::size_t i = b; i < e; ++i)
            project_membrane(material_, packed_membranes_[i], isotropic, 1.0, ctx, &lambda_membrane_[i]);
        else
          for (std::size_t i = b; i < e; ++i)
            project_membrane(material_, packed_membranes_[i], isotropic, 1.0, ctx, nullptr);
        break;
      case ISOMETRIC_BATCHES:
        project_isometric_hinge_batches(&isometric_batches_.batches[b], e - b, kb, xw, ctx,
                                        xpbd ? &lambda_isometric_[3 * BATCH_LANES * b] : nullptr);
        break;
      case ISOMETRIC:
        if (xpbd)
          for (std::size_t i = b; i < e; ++i)
            project_isometric_hinge(set_.isometric_hinges[i], kb, ctx, &lambda_isometric_[3 * i]);
        else
          for (std::size_t i = b; i < e; ++i)
            project_isometric_hinge(set_.isometric_hinges[i], kb, ctx, nullptr);
        break;
      case DIHEDRAL_BATCHES:
        project_dihedral_hinge_batches(&dihedral_batches_.batches[b], e - b, kb, xw, ctx,
                                       xpbd ? &lambda_dihedral_[BATCH_LANES * b] : nullptr);
        break;
      case DIHEDRAL:
        for (std::size_t i = b; i < e; ++i)
          project_dihedral_hinge(set_.dihedral_hinges[i], kb, ctx,
                                 xpbd ? &lambda_dihedral_[i] : nullptr);
        break;
      case ANISOTROPIC:
        for (std::size_t i = b; i < e; ++i) {
          ProjectionContext c = ctx;
          c.orientation = aniso_orientation_[i];
          if (!xpbd && settings_.k_a_in_projection)
            project_anisotropic_paper(aniso_, packed_aniso_[i], aniso_data_[i],
                                      set_.anisotropic_k_a[i], aniso_normal_[i], c);
          else
            project_membrane(aniso_, packed_aniso_[i], aniso_data_[i], 1.0, c,
                             xpbd ? &lambda_aniso_[i] : nullptr);
        }
        break;
      case ANISO_BATCHES:
        if constexpr (BatchedAnisoProjection<A>::value)
          project_aniso_batches(aniso_, &aniso_batches_.batches[b], e - b, xw, ctx,
                                xpbd ? &lambda_aniso_[BATCH_LANES * b] : nullptr,
                                !xpbd && settings_.k_a_in_projection);
        break;
      case REGION_MEMBRANES:
      case INTERFACE_MEMBRANES:
      case REGION_ISOMETRIC:
      case INTERFACE_ISOMETRIC: {
        // Items are parts (or the one interface group): every colour range of the group.
        const bool membranes = kind == REGION_MEMBRANES || kind == INTERFACE_MEMBRANES;
        const bool interface = kind == INTERFACE_MEMBRANES || kind == INTERFACE_ISOMETRIC;
        const std::vector<std::size_t>& off =
            membranes ? membrane_batches_.offsets : isometric_batches_.offsets;
        const std::size_t C =
            static_cast<std::size_t>(membranes ? membrane_num_colours_ : isometric_num_colours_);
        for (std::size_t g = interface ? REGIONS : b; g < (interface ? REGION_GROUPS : e); ++g)
          for (std::size_t c = 0; c < C; ++c)
            project_range(membranes ? MEMBRANE_BATCHES : ISOMETRIC_BATCHES, off[g * C + c],
                          off[g * C + c + 1], ctx);
        break;
      }
      case PACK:
        pack_padded(ctx.x, ctx.w, row_vertex_.data(), b, e, xw);
        break;
      case UNPACK:
        unpack_padded(xw, row_vertex_.data(), b, e, ctx.x);
        break;
      default:
        break;
    }
  }

  void solve_impl(Positions& x, const Eigen::VectorXd& inv_mass) {
    ProjectionContext ctx;
    ctx.x = x.data();
    ctx.w = inv_mass.data();
    ctx.energy_floor = energy_floor_;
    ctx.alpha_tilde = 1.0 / (settings_.dt * settings_.dt);  // alpha = 1 (math-spec 9.2)
    const bool xpbd = settings_.kind == SolverKind::Xpbd;
    if (xpbd) {
      std::fill(lambda_membrane_.begin(), lambda_membrane_.end(), 0.0);
      std::fill(lambda_isometric_.begin(), lambda_isometric_.end(), 0.0);
      std::fill(lambda_dihedral_.begin(), lambda_dihedral_.end(), 0.0);
      std::fill(lambda_aniso_.begin(), lambda_aniso_.end(), 0.0);
    }
    if (!set_.anisotropic.empty()) freeze_anisotropic_frames(x);
    if (coloured_) {
      const std::size_t n = static_cast<std::size_t>(x.rows());
      if (!schedule_built_ || n != padded_.size()) {  // first call (or a new vertex count)
        const std::vector<ColourPhase> phases = sweep_phases(n);
        schedule_ = ColourSchedule(phases, settings_.iterations, arena_->arena().max_concurrency());
        padded_.resize(n);
        // Vertices past the constraints' largest id keep their own row.
        for (std::size_t v = row_vertex_.size(); v < n; ++v)
          row_vertex_.push_back(static_cast<int>(v));
        first_padded_ = !phases.empty() && padded_kind(phases.front().kind);
        last_padded_ = !phases.empty() && (phases.back().kind == PACK ||
                                           (phases.back().kind != UNPACK && padded_kind(phases.back().kind)));
        schedule_built_ = true;
      }
      // The copies in parallel too (row by row: the same values); serial, they were a large
      // share of the solve at 16 threads (lab/pages/scale.md, "Sixteen cores").
      auto rows = [&](auto copy) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, COPY_GRAIN),
                          [&](const tbb::blocked_range<std::size_t>& r) { copy(r.begin(), r.end()); });
      };
      if (first_padded_)
        rows([&](std::size_t b, std::size_t e) {
          pack_padded(ctx.x, ctx.w, row_vertex_.data(), b, e, padded_.data());
        });
      schedule_.run([&](int kind, std::size_t b, std::size_t e) { project_range(kind, b, e, ctx); });
      if (last_padded_)
        rows([&](std::size_t b, std::size_t e) {
          unpack_padded(padded_.data(), row_vertex_.data(), b, e, ctx.x);
        });
      return;
    }
    for (int it = 0; it < settings_.iterations; ++it) {
      project_range(MEMBRANES, 0, set_.membranes.size(), ctx);
      project_range(ISOMETRIC, 0, set_.isometric_hinges.size(), ctx);
      project_range(DIHEDRAL, 0, set_.dihedral_hinges.size(), ctx);
      project_range(ANISOTROPIC, 0, set_.anisotropic.size(), ctx);
    }
  }

  /// Coloured order: the anisotropic faces in batches on the padded rows, and where each face's
  /// lane is (the per-solve normal and orientation are written there).
  void make_aniso_layout() {
    aniso_batches_ = make_aniso_batches(renamed(packed_aniso_, vertex_row_), aniso_data_,
                                        set_.anisotropic_k_a, aniso_colours_);
    aniso_lane_.resize(set_.anisotropic.size());
    for (std::size_t c = 0; c + 1 < aniso_colours_.size(); ++c)
      for (std::size_t i = aniso_colours_[c]; i < aniso_colours_[c + 1]; ++i)
        aniso_lane_[i] = BATCH_LANES * aniso_batches_.offsets[c] + (i - aniso_colours_[c]);
  }

  /// Freezes, for the solve, each anisotropic face's unit normal (for the k_A term, math-spec
  /// 9.3 R) and, in the inversion-aware mode, its orientation s = sign(n . n_ref) with n_ref the
  /// normalized sum of the area-weighted vertex normals of its corners (math-spec 4.2).
  void freeze_anisotropic_frames(const Positions& x) {
    aniso_frames::face_normals(set_.anisotropic, x, aniso_normal_);
    if (settings_.inversion_aware && faces_.rows() > 0)
      aniso_frames::inversion_orientations(set_.anisotropic, faces_, x, aniso_normal_,
                                           vertex_normal_, aniso_orientation_);
    aniso_frames::write_into_batches(aniso_lane_, aniso_normal_, aniso_orientation_,
                                     aniso_batches_);
  }

  M material_;
  A aniso_;
  ConstraintSet set_;  ///< in sweep order (by colour in the Coloured order)
  SolverSettings settings_;
  Faces faces_;
  double energy_floor_;
  std::vector<double> lambda_membrane_;
  std::vector<double> lambda_isometric_;
  std::vector<double> lambda_dihedral_;
  std::vector<double> lambda_aniso_;
  std::vector<Vec3> aniso_normal_;
  std::vector<double> aniso_orientation_;
  Positions vertex_normal_;
  bool coloured_ = false;
  /// Coloured order in the regional layout (see REGIONS): the membrane and isometric ranges are
  /// then REGION_GROUPS x colours (group-major), not one per colour.
  bool regional_ = false;
  int membrane_num_colours_ = 0, isometric_num_colours_ = 0;
  std::vector<int> row_vertex_;  ///< Coloured order: the vertex of each padded row
  std::vector<int> vertex_row_;  ///< its inverse, over the constraints' vertex ids
  ColourOffsets membrane_colours_, isometric_colours_, dihedral_colours_, aniso_colours_;
  /// set_.membranes, packed, same order; freed once membrane batches hold them (Coloured order)
  std::vector<PackedMembrane> packed_membranes_;
  std::vector<PackedMembrane> packed_aniso_;      ///< set_.anisotropic, packed, same order
  std::vector<ElementMaterialData> aniso_data_;   ///< fibre of each anisotropic face
  std::optional<ArenaLease> arena_;  ///< Coloured order only: run_arena(settings.threads)
  ColourSchedule schedule_;          ///< Coloured order only: the phases of a solve (first solve)
  bool schedule_built_ = false;
  bool first_padded_ = false;        ///< a sweep starts on padded_ (pack before the first)
  bool last_padded_ = false;         ///< a sweep ends on padded_ (unpack after the last)
  std::vector<PaddedVertex> padded_; ///< Coloured order: the batches' state (x, y, z, w rows)
  MembraneRestSlots rest_slots_;  ///< set_membrane_rest's map
  HingeRestSlots hinge_slots_;    ///< set_dihedral_rest_angle's
  ColouredBatches<MembraneBatch> membrane_batches_;    ///< Coloured order, StVK only
  ColouredBatches<IsometricBatch> isometric_batches_;  ///< Coloured order only
  ColouredBatches<DihedralBatch> dihedral_batches_;    ///< Coloured order only
  ColouredBatches<AnisoBatch> aniso_batches_;          ///< Coloured order, fibre energies only
  std::vector<std::size_t> aniso_lane_;  ///< 4 batch + lane of each anisotropic face (batched)
};

}  // namespace

std::unique_ptr<ConstraintSolver> make_constraint_solver(MaterialKind material,
                                                         const MaterialParams& params,
                                                         ConstraintSet constraints,
                                                         const SolverSettings& settings,
                                                         const Faces& faces) {
  if (settings.threads < 0) throw std::invalid_argument("solver threads must be >= 0");
  const double energy_floor = skip_energy_floor(material, settings.aniso, params);
  if (settings.aniso == AnisoKind::None) constraints.anisotropic.clear();
  return with_material(material, params, [&](const auto& m) -> std::unique_ptr<ConstraintSolver> {
    return with_aniso(settings.aniso, params, [&](const auto& a) -> std::unique_ptr<ConstraintSolver> {
      using M = std::decay_t<decltype(m)>;
      using A = std::decay_t<decltype(a)>;
      return std::make_unique<GaussSeidelSolver<M, A>>(m, a, energy_floor, std::move(constraints),
                                                       settings, faces);
    });
  });
}

}  // namespace shellcontract
