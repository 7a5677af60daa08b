// Seeded deformation gradients and fibres shared by the material tests: general, compressed,
// stretched, inverted-in-plane (det < 0), near-degenerate, fibre-aligned and upper-triangular
// (the form the edge-aligned element frame produces). Fixed seed only.
#pragma once

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "material/polar2.hpp"
#include "shellcontract/material.hpp"
#include "shellcontract/types.hpp"
#include "support/fd_check.hpp"

namespace shellcontract::test {

/// Parameters used by every material test: all different, so a swapped parameter shows up.
inline MaterialParams test_params() {
  MaterialParams p;
  p.mu = 1.3;
  p.lambda = 0.7;
  p.c10 = 0.4;
  p.c01 = 0.25;
  p.mu_aniso = 1.7;
  p.fiber_target = 0.8;
  return p;
}

/// Rotation by theta in the plane.
inline Mat2 rot2(double theta) {
  Mat2 Q;
  Q << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  return Q;
}

/// One test input: F (2x2 Fbar) and the unit fibre a (rest frame).
struct FCase {
  std::string label;
  Mat2 F;
  Vec2 a;

  ElementMaterialData data() const {
    ElementMaterialData d;
    d.fiber = a;
    return d;
  }
  /// For SCOPED_TRACE: everything needed to reproduce the case.
  std::string describe() const {
    std::ostringstream o;
    o << label << ": F = " << matrix_string(F) << ", a = " << matrix_string(Vec2(a))
      << ", det F = " << F.determinant();
    return o.str();
  }
};

/// The shared case list (fixed seed). Categories and sizes are part of the contract of the
/// tests that filter them, which check that enough of each category survives.
inline std::vector<FCase> material_cases() {
  std::mt19937 rng(20200610);
  constexpr double PI = 3.14159265358979323846;
  std::uniform_real_distribution<double> angle(-PI, PI);
  auto uni = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  auto unit = [&] {
    const double t = angle(rng);
    return Vec2(std::cos(t), std::sin(t));
  };
  auto svd_form = [&](double s1, double s2) {
    return Mat2(rot2(angle(rng)) * Vec2(s1, s2).asDiagonal() * rot2(angle(rng)));
  };
  std::vector<FCase> out;
  for (int k = 0; k < 20; ++k) {  // near identity, det > 0
    Mat2 H;
    H << uni(-0.6, 0.6), uni(-0.6, 0.6), uni(-0.6, 0.6), uni(-0.6, 0.6);
    out.push_back({"general", Mat2::Identity() + H, unit()});
  }
  for (int k = 0; k < 20; ++k) {  // any entries, either determinant sign
    Mat2 F;
    F << uni(-1.5, 1.5), uni(-1.5, 1.5), uni(-1.5, 1.5), uni(-1.5, 1.5);
    out.push_back({"random", F, unit()});
  }
  for (int k = 0; k < 10; ++k)
    out.push_back({"compressed", svd_form(uni(0.2, 0.9), uni(0.2, 0.9)), unit()});
  for (int k = 0; k < 10; ++k)
    out.push_back({"stretched", svd_form(uni(1.1, 2.0), uni(1.1, 2.0)), unit()});
  for (int k = 0; k < 15; ++k)
    out.push_back({"inverted", svd_form(uni(0.2, 2.0), -uni(0.2, 2.0)), unit()});
  for (int k = 0; k < 10; ++k) {  // |det F| ~ 1e-4: a nearly collapsed triangle, both signs
    const double sgn = (k % 2 == 0) ? 1.0 : -1.0;
    out.push_back({"near-degenerate", svd_form(uni(0.5, 1.5), sgn * uni(1e-4, 9e-4)), unit()});
  }
  for (int k = 0; k < 10; ++k) {  // F a parallel to a; fibre stretch away from 1 and from 0.8
    const Vec2 a = unit();
    const Vec2 a_perp(-a.y(), a.x());
    const double l1 = (k % 2 == 0) ? uni(0.3, 0.7) : uni(1.2, 1.8);
    const Vec2 b = uni(0.3, 1.5) * unit();
    out.push_back({"fibre-aligned", Mat2(l1 * a * a.transpose() + b * a_perp.transpose()), a});
  }
  for (int k = 0; k < 10; ++k) {  // what triangle_frame() produces: upper triangular
    Mat2 F;
    F << uni(0.3, 2.0), uni(-1.0, 1.0), 0.0, ((k % 3 == 0) ? -1.0 : 1.0) * uni(0.3, 2.0);
    out.push_back({"upper-triangular", F, unit()});
  }
  return out;
}

/// True when every model is smooth in a neighbourhood of F, so that a finite-difference check
/// is meaningful: away from the corotated cone rho = 0, the ARAP sign surface I4 = 0, the fibre
/// guard |F a| -> 0 and the Mooney-Rivlin clamp |J| < 1e-6. Margins are relative and far larger
/// than the largest FD step.
inline bool fd_smooth(const FCase& c) {
  const Mat2& F = c.F;
  const double i5 = fiber_i5(F, c.a);
  const double J = F.determinant();
  return polar2(F).rho >= 0.05 * F.norm() && std::abs(i5 + J) >= 0.05 * (i5 + std::abs(J)) &&
         std::sqrt(i5) >= 0.05 && std::abs(J) >= 1e-5;
}

}  // namespace shellcontract::test
