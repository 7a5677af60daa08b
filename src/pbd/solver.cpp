#include "shellcontract/pbd/solver.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "shellcontract/bending/isometric_bending.hpp"
#include "shellcontract/pbd/colouring.hpp"
#include "shellcontract/pbd/constraint_kernels.hpp"

namespace shellcontract {
namespace {

/// Skip threshold of math-spec 9.1(d): E <= 1e-16 mu Abar.
constexpr double ENERGY_FLOOR_RELATIVE = 1e-16;

Vec3 row(const Positions& x, int i) { return Vec3(x(i, 0), x(i, 1), x(i, 2)); }

/// Constraints per TBB task in the Coloured order. A membrane projection takes ~10 ns, so a
/// chunk is a few microseconds of work, well above the cost of spawning it; colours smaller than
/// two chunks run on the calling thread.
constexpr std::size_t COLOUR_GRAIN = 256;

/// Colour ranges of one constraint kind: constraint k of colour c lies in
/// [offsets[c], offsets[c + 1]). The Sequential order is one range over everything.
using ColourOffsets = std::vector<std::size_t>;

/// The solver for one concrete membrane material M and anisotropic energy A: the template makes
/// the per-element material calls direct and inlinable (material.hpp).
template <class M, class A>
class GaussSeidelSolver final : public ConstraintSolver {
 public:
  GaussSeidelSolver(M material, A aniso, double energy_scale, ConstraintSet set,
                    const SolverSettings& settings, Faces faces)
      : material_(std::move(material)),
        aniso_(std::move(aniso)),
        set_(std::move(set)),
        settings_(settings),
        faces_(std::move(faces)),
        energy_floor_(ENERGY_FLOOR_RELATIVE * energy_scale) {
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
      // The value of `automatic` is copied first: binding the static member to the conditional's
      // lvalue would odr-use it, and TBB 2021 does not define it out of line (link error).
      const int automatic = tbb::task_arena::automatic;
      arena_ = std::make_unique<tbb::task_arena>(settings_.threads > 0 ? settings_.threads : automatic);
    } else {
      membrane_colours_ = {0, set_.membranes.size()};
      isometric_colours_ = {0, set_.isometric_hinges.size()};
      dihedral_colours_ = {0, set_.dihedral_hinges.size()};
      aniso_colours_ = {0, set_.anisotropic.size()};
    }
    packed_membranes_.reserve(set_.membranes.size());
    for (const MembraneConstraint& c : set_.membranes) packed_membranes_.push_back(pack_membrane(c));
    packed_aniso_.reserve(set_.anisotropic.size());
    aniso_data_.reserve(set_.anisotropic.size());
    for (const MembraneConstraint& c : set_.anisotropic) {
      packed_aniso_.push_back(pack_membrane(c));
      aniso_data_.push_back(c.data);
    }
    if (settings_.kind == SolverKind::Xpbd) {
      lambda_membrane_.resize(set_.membranes.size());
      lambda_isometric_.resize(3 * set_.isometric_hinges.size());
      lambda_dihedral_.resize(set_.dihedral_hinges.size());
      lambda_aniso_.resize(set_.anisotropic.size());
    }
    aniso_normal_.resize(set_.anisotropic.size(), Vec3::Zero());
    aniso_orientation_.resize(set_.anisotropic.size(), 1.0);
  }

  void solve(Positions& x, const Eigen::VectorXd& inv_mass) override {
    if (coloured_)
      arena_->execute([&] { solve_impl(x, inv_mass); });
    else
      solve_impl(x, inv_mass);
  }

  ColourCounts colour_counts() const override {
    ColourCounts n;
    if (!coloured_) return n;
    n.membrane = static_cast<int>(membrane_colours_.size()) - 1;
    n.isometric = static_cast<int>(isometric_colours_.size()) - 1;
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

  /// Runs body(begin, end) over every range of `colours` in sequence: directly in the
  /// Sequential order, split over the arena's threads within each colour in the Coloured order.
  /// Constraints of one colour share no vertex, so how a colour is split does not change a bit.
  template <class Body>
  void sweep(const ColourOffsets& colours, const Body& body) const {
    for (std::size_t c = 0; c + 1 < colours.size(); ++c) {
      const std::size_t begin = colours[c], end = colours[c + 1];
      if (!coloured_ || end - begin < 2 * COLOUR_GRAIN) {
        body(begin, end);
        continue;
      }
      tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, COLOUR_GRAIN),
                        [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); },
                        tbb::static_partitioner());
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
    const bool paper_k_a = !xpbd && settings_.k_a_in_projection;
    const double kb = settings_.k_bending;
    const ElementMaterialData isotropic{};  // isotropic membranes ignore the fibre
    for (int it = 0; it < settings_.iterations; ++it) {
      // The xpbd test is outside the inner loops so each loop body is branch-free.
      sweep(membrane_colours_, [&](std::size_t b, std::size_t e) {
        if (xpbd)
          for (std::size_t i = b; i < e; ++i)
            project_membrane(material_, packed_membranes_[i], isotropic, 1.0, ctx, &lambda_membrane_[i]);
        else
          for (std::size_t i = b; i < e; ++i)
            project_membrane(material_, packed_membranes_[i], isotropic, 1.0, ctx, nullptr);
      });
      sweep(isometric_colours_, [&](std::size_t b, std::size_t e) {
        if (xpbd)
          for (std::size_t i = b; i < e; ++i)
            project_isometric_hinge(set_.isometric_hinges[i], kb, ctx, &lambda_isometric_[3 * i]);
        else
          for (std::size_t i = b; i < e; ++i)
            project_isometric_hinge(set_.isometric_hinges[i], kb, ctx, nullptr);
      });
      sweep(dihedral_colours_, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          project_dihedral_hinge(set_.dihedral_hinges[i], kb, ctx,
                                 xpbd ? &lambda_dihedral_[i] : nullptr);
      });
      sweep(aniso_colours_, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          ProjectionContext c = ctx;
          c.orientation = aniso_orientation_[i];
          if (paper_k_a)
            project_anisotropic_paper(aniso_, packed_aniso_[i], aniso_data_[i],
                                      set_.anisotropic_k_a[i], aniso_normal_[i], c);
          else
            project_membrane(aniso_, packed_aniso_[i], aniso_data_[i], 1.0, c,
                             xpbd ? &lambda_aniso_[i] : nullptr);
        }
      });
    }
  }

  template <class Model>
  static void add_face_energies(const Model& m, const std::vector<MembraneConstraint>& set,
                                const Positions& x, const std::vector<double>* orientation,
                                Eigen::VectorXd& e) {
    for (std::size_t i = 0; i < set.size(); ++i) {
      const MembraneConstraint& c = set[i];
      if (c.face < 0 || c.face >= e.size()) continue;
      TriangleFrame fr;
      const double s = orientation ? (*orientation)[i] : 1.0;
      if (!triangle_frame(row(x, c.v[0]), row(x, c.v[1]), row(x, c.v[2]), c.Dm_inv, c.rest_area, s, fr))
        continue;
      if (!fr.regular && m.frame_dependent()) continue;
      e(c.face) += c.rest_area * m.psi(fr.F, c.data);
    }
  }

  template <class Model>
  static double membrane_energy(const Model& m, const std::vector<MembraneConstraint>& set,
                                const Positions& x, const std::vector<double>* orientation) {
    double sum = 0.0;
    for (std::size_t i = 0; i < set.size(); ++i) {
      const MembraneConstraint& c = set[i];
      TriangleFrame fr;
      const double s = orientation ? (*orientation)[i] : 1.0;
      if (!triangle_frame(row(x, c.v[0]), row(x, c.v[1]), row(x, c.v[2]), c.Dm_inv, c.rest_area, s, fr))
        continue;
      if (!fr.regular && m.frame_dependent()) continue;
      sum += c.rest_area * m.psi(fr.F, c.data);
    }
    return sum;
  }

  /// Freezes, for the solve, each anisotropic face's unit normal (for the k_A term, math-spec
  /// 9.3 R) and, in the inversion-aware mode, its orientation s = sign(n . n_ref) with n_ref the
  /// normalized sum of the area-weighted vertex normals of its corners (math-spec 4.2).
  void freeze_anisotropic_frames(const Positions& x) {
    for (std::size_t i = 0; i < set_.anisotropic.size(); ++i) {
      const auto& v = set_.anisotropic[i].v;
      const Vec3 N = (row(x, v[0]) - row(x, v[2])).cross(row(x, v[1]) - row(x, v[2]));
      const double len = N.norm();
      aniso_normal_[i] = len > 0.0 ? Vec3(N / len) : Vec3::Zero();  // collapsed: no inward push
    }
    if (!settings_.inversion_aware || faces_.rows() == 0) return;
    vertex_normal_.setZero(x.rows(), 3);
    for (Eigen::Index j = 0; j < faces_.rows(); ++j) {
      const Vec3 N = (row(x, faces_(j, 0)) - row(x, faces_(j, 2)))
                         .cross(row(x, faces_(j, 1)) - row(x, faces_(j, 2)));
      for (int k = 0; k < 3; ++k) vertex_normal_.row(faces_(j, k)) += N.transpose();
    }
    for (std::size_t i = 0; i < set_.anisotropic.size(); ++i) {
      const auto& v = set_.anisotropic[i].v;
      Vec3 ref = Vec3::Zero();
      for (int k = 0; k < 3; ++k) {
        const Vec3 nv = row(vertex_normal_, v[k]);
        const double len = nv.norm();
        if (len > 0.0) ref += nv / len;
      }
      // Tie (n . n_ref = 0, or no reference) counts as not inverted (math-spec 5 tie rule).
      aniso_orientation_[i] = aniso_normal_[i].dot(ref) < 0.0 ? -1.0 : 1.0;
    }
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
  ColourOffsets membrane_colours_, isometric_colours_, dihedral_colours_, aniso_colours_;
  std::vector<PackedMembrane> packed_membranes_;  ///< set_.membranes, packed, same order
  std::vector<PackedMembrane> packed_aniso_;      ///< set_.anisotropic, packed, same order
  std::vector<ElementMaterialData> aniso_data_;   ///< fibre of each anisotropic face
  std::unique_ptr<tbb::task_arena> arena_;        ///< Coloured order only: settings.threads
};

}  // namespace

std::unique_ptr<ConstraintSolver> make_constraint_solver(MaterialKind material,
                                                         const MaterialParams& params,
                                                         ConstraintSet constraints,
                                                         const SolverSettings& settings,
                                                         const Faces& faces) {
  if (settings.threads < 0) throw std::invalid_argument("solver threads must be >= 0");
  const double energy_scale =
      std::max({params.mu, params.lambda, 2.0 * (params.c10 + params.c01), params.mu_aniso});
  if (settings.aniso == AnisoKind::None) constraints.anisotropic.clear();
  return with_material(material, params, [&](const auto& m) -> std::unique_ptr<ConstraintSolver> {
    return with_aniso(settings.aniso, params, [&](const auto& a) -> std::unique_ptr<ConstraintSolver> {
      using M = std::decay_t<decltype(m)>;
      using A = std::decay_t<decltype(a)>;
      return std::make_unique<GaussSeidelSolver<M, A>>(m, a, energy_scale, std::move(constraints),
                                                       settings, faces);
    });
  });
}

}  // namespace shellcontract
