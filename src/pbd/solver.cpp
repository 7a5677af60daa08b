#include "shellcontract/pbd/solver.hpp"

#include <utility>
#include <vector>

#include "shellcontract/bending/isometric_bending.hpp"
#include "shellcontract/pbd/constraint_kernels.hpp"

namespace shellcontract {
namespace {

/// Skip threshold of math-spec 9.1(d): E <= 1e-16 mu Abar.
constexpr double ENERGY_FLOOR_RELATIVE = 1e-16;

/// The solver for one concrete membrane material type M: the template makes the per-element
/// material calls direct and inlinable (material.hpp).
template <class M>
class GaussSeidelSolver final : public ConstraintSolver {
 public:
  GaussSeidelSolver(M material, double energy_scale, ConstraintSet set,
                    const SolverSettings& settings)
      : material_(std::move(material)),
        set_(std::move(set)),
        settings_(settings),
        energy_floor_(ENERGY_FLOOR_RELATIVE * energy_scale) {
    if (settings_.kind == SolverKind::Xpbd) {
      lambda_membrane_.resize(set_.membranes.size());
      lambda_isometric_.resize(3 * set_.isometric_hinges.size());
      lambda_dihedral_.resize(set_.dihedral_hinges.size());
    }
  }

  void solve(Positions& x, const Eigen::VectorXd& inv_mass) override {
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
    }
    const double kb = settings_.k_bending;
    for (int it = 0; it < settings_.iterations; ++it) {
      for (std::size_t i = 0; i < set_.membranes.size(); ++i)
        project_membrane(material_, set_.membranes[i], 1.0, ctx,
                         xpbd ? &lambda_membrane_[i] : nullptr);
      for (std::size_t i = 0; i < set_.isometric_hinges.size(); ++i)
        project_isometric_hinge(set_.isometric_hinges[i], kb, ctx,
                                xpbd ? &lambda_isometric_[3 * i] : nullptr);
      for (std::size_t i = 0; i < set_.dihedral_hinges.size(); ++i)
        project_dihedral_hinge(set_.dihedral_hinges[i], kb, ctx,
                               xpbd ? &lambda_dihedral_[i] : nullptr);
    }
  }

  ConstraintEnergies energies(const Positions& x) const override {
    ConstraintEnergies e;
    auto X = [&](int i) { return Vec3(x.row(i).transpose()); };
    for (const MembraneConstraint& c : set_.membranes) {
      TriangleFrame fr;
      if (!triangle_frame(X(c.v[0]), X(c.v[1]), X(c.v[2]), c.Dm_inv, c.rest_area, 1.0, fr)) continue;
      if (!fr.regular && material_.frame_dependent()) continue;
      e.membrane += c.rest_area * material_.psi(fr.F, c.data);
    }
    for (const IsometricHingeConstraint& c : set_.isometric_hinges) {
      const Vec3 h = c.K(0) * X(c.v[0]) + c.K(1) * X(c.v[1]) + c.K(2) * X(c.v[2]) + c.K(3) * X(c.v[3]);
      e.bending += settings_.k_bending * 0.5 * c.three_over_area * h.squaredNorm();
    }
    for (const DihedralHingeConstraint& c : set_.dihedral_hinges)
      e.bending += dihedral_bending_energy(c.rest, settings_.k_bending, X(c.v[0]), X(c.v[1]),
                                           X(c.v[2]), X(c.v[3]));
    return e;
  }

  const ConstraintSet& constraints() const override { return set_; }

 private:
  M material_;
  ConstraintSet set_;
  SolverSettings settings_;
  double energy_floor_;
  std::vector<double> lambda_membrane_;
  std::vector<double> lambda_isometric_;
  std::vector<double> lambda_dihedral_;
};

}  // namespace

std::unique_ptr<ConstraintSolver> make_constraint_solver(MaterialKind material,
                                                         const MaterialParams& params,
                                                         ConstraintSet constraints,
                                                         const SolverSettings& settings) {
  const double energy_scale = std::max({params.mu, params.lambda, 2.0 * (params.c10 + params.c01)});
  return with_material(material, params, [&](const auto& m) -> std::unique_ptr<ConstraintSolver> {
    using M = std::decay_t<decltype(m)>;
    return std::make_unique<GaussSeidelSolver<M>>(m, energy_scale, std::move(constraints), settings);
  });
}

}  // namespace shellcontract
