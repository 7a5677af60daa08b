// SelfCollision's set-up (the rest state's excluded and near pairs) and its public calls, which
// forward to the stages (state.hpp lists them).
#include "collision/self_collision/state.hpp"

namespace shellcontract {

// A pair can come within delta in the step only if its swept boxes, each grown by its vertices'
// regions (m/2 and the rounding of the region bounds, at most u (M + m/2); M = max |coordinate|,
// u the unit roundoff), come within delta on every axis: if the boxes' gap G <= delta + m +
// 2u (M + m/2). Boxes grown by I overlap for every G <= 2I, their rounded bounds included
// (rounding is monotone: hi + I >= lo' - I gives fl(hi + I) >= fl(lo' - I)). So I = (delta +
// m)/2 + s covers the bound when s >= u (M + m/2) plus the rounding of I itself, which s = 4u (M
// + delta + m) does. The inflation was delta + m/2, a band of gaps up to 2 delta + m (6 delta)
// where delta + m (5 delta) are needed, and the wider band gave measurably more candidates
// (lab/scripts/scale_benchmark.py's pairs per face; lab/history.md).
double broad_phase_inflation(const CollisionOptions& options, double max_abs) {
  constexpr double u = std::numeric_limits<double>::epsilon() / 2.0;
  const double band = options.delta + options.region_margin * options.delta;
  return 0.5 * band + 4.0 * u * (max_abs + band);
}

SelfCollision::Impl::Impl(const Faces& faces, const Positions& rest,
                          const CollisionOptions& options)
    : topo_(make_collision_topology(faces, static_cast<int>(rest.rows()))),
      options_(options),
      workers_(std::make_unique<Workers>(options.threads)) {
  // Pairs that touch (distance 0) in the rest state cannot be separated by a response that
  // keeps each pair on its starting side: exclude them for the whole run. Pairs closer than
  // delta (but not touching) are the input's own thin features: the response leaves them at
  // their rest distance (a shell at rest stays at rest), but the fail-safe still keeps them
  // from crossing.
  find_candidates(rest, rest, topo_, options_.delta, candidates_, nullptr, options_.method);
  CcdOptions touch, near;
  touch.tolerance = 0.0;
  near.tolerance = options_.delta;
  for_each_pair(
      candidates_, topo_,
      [&](CcdPrimitive kind, const std::array<int, 2>& pair, const std::array<int, 4>& v) {
        CcdStencil s0, s1;
        gather(rest, rest, v, s0, s1);
        const bool vf = kind == CcdPrimitive::VertexFace;
        if (primitive_ccd(kind, s0, s1, touch).hit)
          (vf ? excluded_vf_ : excluded_ee_).push_back(pair);
        else if (primitive_ccd(kind, s0, s1, near).hit)
          (vf ? near_vf_ : near_ee_).push_back(pair);
      });
  // Sorted for the binary searches of broad_phase (the Grid's candidates are in cell order).
  for (auto* list : {&excluded_vf_, &excluded_ee_, &near_vf_, &near_ee_})
    std::sort(list->begin(), list->end());
  moved_.assign(static_cast<std::size_t>(rest.rows()), 0);
}

SelfCollision::Impl::~Impl() {
  if (!spec_enqueued_) return;
  try {
    workers_->arena.execute([&] { workers_->background.wait(); });
  } catch (...) {
    // The task's own failure does not matter any more; it must only not outlive the members.
  }
}

SelfCollision::SelfCollision(const Faces& faces, const Positions& rest,
                             const CollisionOptions& options)
    : impl_(std::make_unique<Impl>(faces, rest, options)) {}

SelfCollision::~SelfCollision() = default;

void SelfCollision::resolve(const Positions& x0, Positions& x1, const Eigen::VectorXd& w,
                            CollisionStepStats& stats) {
  impl_->resolve(x0, x1, w, stats);
}

void SelfCollision::predict(const Positions& x0, const Positions& x_guess,
                            const Eigen::VectorXd& w) {
  impl_->predict(x0, x_guess, w);
}

const std::vector<Contact>& SelfCollision::contact_cache() const {
  return impl_->previous_contacts_;
}

SelfCollision::PersistentState SelfCollision::persistent_state() const {
  return {impl_->previous_contacts_, impl_->correction_, impl_->skin_};
}

void SelfCollision::restore_persistent_state(PersistentState state) {
  impl_->previous_contacts_ = std::move(state.contact_cache);
  impl_->correction_ = std::move(state.correction);
  impl_->skin_ = std::move(state.skin);
}

bool SelfCollision::live_pairs_consistent() const { return impl_->live_pairs_consistent(); }

std::pair<std::vector<std::array<int, 2>>, std::vector<std::array<int, 2>>>
SelfCollision::candidate_pairs() const {
  return impl_->candidate_pairs();
}

std::size_t SelfCollision::excluded_pairs() const {
  return impl_->excluded_vf_.size() + impl_->excluded_ee_.size();
}

const CollisionTopology& SelfCollision::topology() const { return impl_->topo_; }

}  // namespace shellcontract
