#include "shellcontract/observer.hpp"

namespace shellcontract {

void RunTotals::add(const FrameMetrics& m) {
  const CollisionStepStats& c = m.collision;
  no_culling_ += static_cast<double>(c.pairs_no_culling);
  broad_ += static_cast<double>(c.pairs_broad);
  filtered_ += static_cast<double>(c.pairs_filtered);
  tests_ += static_cast<double>(c.narrow_tests);
  axis_culls_ += static_cast<double>(c.axis_culls);
  contacts_ += static_cast<double>(c.contacts);
  failsafe_ += static_cast<double>(c.failsafe_vertices);
  broad_calls_ += c.broad_phase_calls;
  filter_tests_ += static_cast<double>(c.filter_tests);
  rounds_ += c.rounds;
  rescans_full_ += c.rescans_full;
  rescans_in_zone_ += c.rescans_in_zone;
  speculative_ += c.speculative;
  escaped_ += static_cast<double>(c.escaped_vertices);
  background_s_ += c.background_seconds;
  wait_s_ += c.wait_seconds;
  bg_grid_s_ += c.background_grid_seconds;
  bg_cells_s_ += c.background_cell_loop_seconds;
  bg_output_s_ += c.background_output_seconds;
  bg_records_s_ += c.background_records_seconds;
  grid_s_ += c.broad_grid_seconds;
  cells_s_ += c.broad_cell_loop_seconds;
  output_s_ += c.broad_output_seconds;
  records_s_ += c.broad_records_seconds;
  predict_s_ += c.predict_seconds;
  broad_s_ += c.broad_seconds;
  filter_s_ += c.filter_seconds;
  narrow_s_ += c.narrow_seconds;
  response_s_ += c.response_seconds;
  collision_s_ += c.seconds;
  solve_s_ += m.solve_seconds;
  step_s_ += m.step_seconds;
}

std::vector<std::pair<std::string, double>> RunTotals::per_step(int frames) const {
  const double n = frames > 0 ? frames : 1;
  return {
      {"pairs_no_culling_per_step", no_culling_ / n},
      {"pairs_after_broad_phase_per_step", broad_ / n},
      {"pairs_after_filter_per_step", filtered_ / n},
      {"narrow_queries_per_step", tests_ / n},
      {"separating_axis_culls_per_step", axis_culls_ / n},
      {"cubic_solves_per_step", (tests_ - axis_culls_) / n},
      {"contacts_per_step", contacts_ / n},
      {"failsafe_vertices_total", failsafe_},
      {"broad_phase_calls_per_step", broad_calls_ / n},
      {"filter_tests_per_step", filter_tests_ / n},
      {"rounds_per_step", rounds_ / n},
      {"rescans_full_per_step", rescans_full_ / n},
      {"rescans_in_zone_per_step", rescans_in_zone_ / n},
      {"speculative_broad_phase_steps", speculative_},
      {"escaped_vertices_per_speculative_step", speculative_ > 0 ? escaped_ / speculative_ : 0.0},
      {"background_broad_phase_ms_per_step", 1e3 * background_s_ / n},
      {"background_wait_ms_per_step", 1e3 * wait_s_ / n},
      {"background_grid_ms_per_step", 1e3 * bg_grid_s_ / n},
      {"background_cell_loop_ms_per_step", 1e3 * bg_cells_s_ / n},
      {"background_pair_output_ms_per_step", 1e3 * bg_output_s_ / n},
      {"background_records_ms_per_step", 1e3 * bg_records_s_ / n},
      {"prediction_ms_per_step", 1e3 * predict_s_ / n},
      {"broad_phase_ms_per_step", 1e3 * broad_s_ / n},
      {"broad_phase_grid_ms_per_step", 1e3 * grid_s_ / n},
      {"broad_phase_cell_loop_ms_per_step", 1e3 * cells_s_ / n},
      {"broad_phase_pair_output_ms_per_step", 1e3 * output_s_ / n},
      {"broad_phase_records_ms_per_step", 1e3 * records_s_ / n},
      {"filter_ms_per_step", 1e3 * filter_s_ / n},
      {"narrow_phase_ms_per_step", 1e3 * narrow_s_ / n},
      {"response_ms_per_step", 1e3 * response_s_ / n},
      {"collision_ms_per_step", 1e3 * collision_s_ / n},
      {"constraint_solve_ms_per_step", 1e3 * solve_s_ / n},
      {"step_ms", 1e3 * step_s_ / n},
  };
}

}  // namespace shellcontract
