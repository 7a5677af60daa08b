// shellcontract run: read, check, contract, write (design.md data flow).
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "command_line.hpp"
#include "json_writer.hpp"
#include "shellcontract/core/error.hpp"
#include "shellcontract/geometry/region_selection.hpp"
#include "shellcontract/material/registry.hpp"
#include "shellcontract/mesh/eigen_point_map.hpp"
#include "shellcontract/mesh/io.hpp"
#include "shellcontract/sim/fields.hpp"
#include "shellcontract/sim/simulator.hpp"

namespace po = boost::program_options;

namespace shellcontract::cli {
namespace {

SolverKind parse_solver(const std::string& s) {
  if (s == "pbd") return SolverKind::Pbd;
  if (s == "xpbd") return SolverKind::Xpbd;
  throw UsageError("unknown solver '" + s + "' (expected pbd or xpbd)");
}

BendingModel parse_bending(const std::string& s) {
  if (s == "isometric") return BendingModel::Isometric;
  if (s == "dihedral") return BendingModel::Dihedral;
  if (s == "none") return BendingModel::None;
  throw UsageError("unknown bending model '" + s + "' (expected isometric, dihedral or none)");
}

PressureModel parse_pressure_model(const std::string& s) {
  if (s == "energy") return PressureModel::EnergyConsistent;
  if (s == "paper") return PressureModel::Paper;
  throw UsageError("unknown pressure model '" + s + "' (expected energy or paper)");
}

MassModel parse_mass(const std::string& s) {
  if (s == "area") return MassModel::AreaLumped;
  if (s == "unit") return MassModel::Unit;
  throw UsageError("unknown mass model '" + s + "' (expected area or unit)");
}

FieldColour parse_field_colour(const std::string& s) {
  if (s == "mean") return FieldColour::MeanCurvature;
  if (s == "gaussian") return FieldColour::GaussianCurvature;
  if (s == "pressure") return FieldColour::Pressure;
  if (s == "energy") return FieldColour::EnergyDensity;
  throw UsageError("unknown --fields-colour '" + s + "' (expected mean, gaussian, pressure or energy)");
}

ValidateMode parse_validate(const std::string& s) {
  if (s == "off") return ValidateMode::Off;
  if (s == "end") return ValidateMode::End;
  if (s == "every-frame") return ValidateMode::EveryFrame;
  throw UsageError("unknown validation mode '" + s + "' (expected off, end or every-frame)");
}

InwardTerm parse_inward(const std::string& s) {
  if (s == "projection") return InwardTerm::Projection;
  if (s == "force") return InwardTerm::Force;
  if (s == "none") return InwardTerm::None;
  throw UsageError("unknown inward term '" + s + "' (expected projection, force or none)");
}

Vec3 parse_direction(const std::string& s) {
  Vec3 d;
  char c1 = 0, c2 = 0;
  std::istringstream in(s);
  if (!(in >> d.x() >> c1 >> d.y() >> c2 >> d.z()) || c1 != ',' || c2 != ',' || !(in >> std::ws).eof() ||
      !d.allFinite() || d.norm() == 0.0)
    throw UsageError("--fiber expects 'centre' or a nonzero direction X,Y,Z, got '" + s + "'");
  return d;
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? "|" : "") + v[i];
  return out;
}

const char* CSV_HEADER =
    "frame,time,volume_ratio,energy_membrane,energy_bending,energy_anisotropic,"
    "max_displacement,step_ms,solve_ms,ccd_ms,candidates,contacts,collision_rounds,"
    "failsafe_vertices,new_intersections\n";

std::string csv_row(const FrameMetrics& m) {
  std::ostringstream o;
  o << std::setprecision(17) << m.frame << ',' << m.time << ',' << m.volume_ratio << ','
    << m.energies.membrane << ',' << m.energies.bending << ',' << m.energies.anisotropic << ','
    << m.max_displacement << ',' << m.step_seconds * 1e3 << ',' << m.solve_seconds * 1e3 << ','
    << m.collision.seconds * 1e3 << ',' << m.collision.pairs_broad << ','
    << m.collision.contacts << ',' << m.collision.rounds << ',' << m.collision.failsafe_vertices
    << ',' << m.new_intersections << '\n';
  return o.str();
}

/// Per-stage sums over the run: the paper's Table 2 columns (candidate pairs without culling,
/// after the broad phase, after the filter, cubic solves, and the time of each stage per step).
struct CollisionTotals {
  double no_culling = 0, broad = 0, filtered = 0, tests = 0, axis_culls = 0, contacts = 0,
         failsafe = 0;
  double broad_calls = 0, filter_tests = 0, rounds = 0, speculative = 0, escaped = 0,
         background_s = 0, wait_s = 0, bg_grid_s = 0, bg_cells_s = 0, bg_output_s = 0,
         bg_records_s = 0, predict_s = 0, rescans_full = 0, rescans_in_zone = 0;
  double broad_s = 0, filter_s = 0, narrow_s = 0, response_s = 0, collision_s = 0, solve_s = 0,
         step_s = 0;
  void add(const FrameMetrics& m) {
    const CollisionStepStats& c = m.collision;
    no_culling += static_cast<double>(c.pairs_no_culling);
    broad += static_cast<double>(c.pairs_broad);
    filtered += static_cast<double>(c.pairs_filtered);
    tests += static_cast<double>(c.narrow_tests);
    axis_culls += static_cast<double>(c.axis_culls);
    contacts += static_cast<double>(c.contacts);
    failsafe += static_cast<double>(c.failsafe_vertices);
    broad_calls += c.broad_phase_calls;
    filter_tests += static_cast<double>(c.filter_tests);
    rounds += c.rounds;
    rescans_full += c.rescans_full;
    rescans_in_zone += c.rescans_in_zone;
    speculative += c.speculative;
    escaped += static_cast<double>(c.escaped_vertices);
    background_s += c.background_seconds;
    wait_s += c.wait_seconds;
    bg_grid_s += c.background_grid_seconds;
    bg_cells_s += c.background_cell_loop_seconds;
    bg_output_s += c.background_output_seconds;
    bg_records_s += c.background_records_seconds;
    predict_s += c.predict_seconds;
    broad_s += c.broad_seconds;
    filter_s += c.filter_seconds;
    narrow_s += c.narrow_seconds;
    response_s += c.response_seconds;
    collision_s += c.seconds;
    solve_s += m.solve_seconds;
    step_s += m.step_seconds;
  }
  /// Means per step.
  JsonObject json(int frames) const {
    const double n = frames > 0 ? frames : 1;
    JsonObject o;
    o.add("pairs_no_culling_per_step", no_culling / n).add("pairs_after_broad_phase_per_step", broad / n)
        .add("pairs_after_filter_per_step", filtered / n).add("narrow_queries_per_step", tests / n)
        .add("separating_axis_culls_per_step", axis_culls / n)
        .add("cubic_solves_per_step", (tests - axis_culls) / n)
        .add("contacts_per_step", contacts / n).add("failsafe_vertices_total", failsafe)
        .add("broad_phase_calls_per_step", broad_calls / n).add("filter_tests_per_step", filter_tests / n)
        .add("rounds_per_step", rounds / n)
        .add("rescans_full_per_step", rescans_full / n)
        .add("rescans_in_zone_per_step", rescans_in_zone / n)
        .add("speculative_broad_phase_steps", speculative)
        .add("escaped_vertices_per_speculative_step", speculative > 0 ? escaped / speculative : 0.0)
        .add("background_broad_phase_ms_per_step", 1e3 * background_s / n)
        .add("background_wait_ms_per_step", 1e3 * wait_s / n)
        .add("background_grid_ms_per_step", 1e3 * bg_grid_s / n)
        .add("background_cell_loop_ms_per_step", 1e3 * bg_cells_s / n)
        .add("background_pair_output_ms_per_step", 1e3 * bg_output_s / n)
        .add("background_records_ms_per_step", 1e3 * bg_records_s / n)
        .add("prediction_ms_per_step", 1e3 * predict_s / n)
        .add("broad_phase_ms_per_step", 1e3 * broad_s / n).add("filter_ms_per_step", 1e3 * filter_s / n)
        .add("narrow_phase_ms_per_step", 1e3 * narrow_s / n).add("response_ms_per_step", 1e3 * response_s / n)
        .add("collision_ms_per_step", 1e3 * collision_s / n)
        .add("constraint_solve_ms_per_step", 1e3 * solve_s / n).add("step_ms", 1e3 * step_s / n);
    return o;
  }
};

}  // namespace

int command_run(int argc, char** argv) {
  std::string input, output, log_path, summary_path, solver = "pbd", material = "stvk",
                                                     bending = "isometric", pressure_model = "energy",
                                                     mass = "area";
  SimOptions opt;
  std::string collisions = "on", validate = "off", order = "sequential", warm_start = "on",
              speculative = "auto";
  std::string aniso = "none", regions_arg = "auto", inward = "force", fiber = "centre";
  double young = 0, poisson = 0.3, thickness = 0;
  bool quiet = false;
  bool measure_regions = false;
  std::string fields_prefix, fields_colour = "mean";

  po::options_description desc(
      "usage: shellcontract run INPUT -o OUTPUT [options]\n\n"
      "Contracts a closed triangle mesh (OFF, OBJ, PLY, STL) like a thin elastic shell under an\n"
      "outside pressure. The mesh is normalized to a unit bounding-box diagonal for the\n"
      "simulation (lengths and pressure below are in those units) and scaled back on output.\n"
      "Output keeps the input's vertex and face order.\n\noptions");
  desc.add_options()
      ("help,h", "show this help")
      ("output,o", po::value(&output), "output mesh (format from the extension)")
      ("pressure,p", po::value(&opt.pressure)->default_value(opt.pressure),
       "outside over-pressure P (normalized units; > 0 compresses)")
      ("pressure-model", po::value(&pressure_model)->default_value(pressure_model),
       "energy: f = -P dV/dx (no net force); paper: P * area * unit vertex normal")
      ("frames,n", po::value(&opt.frames)->default_value(opt.frames), "number of time steps")
      ("dt", po::value(&opt.dt)->default_value(opt.dt), "time step (normalized units)")
      ("iterations", po::value(&opt.solver.iterations)->default_value(opt.solver.iterations),
       "Gauss-Seidel sweeps per step (paper: 5)")
      ("order", po::value(&order)->default_value(order),
       "sequential: the paper's Gauss-Seidel order; coloured: parallel by colour, bit-identical "
       "for any thread count")
      ("threads", po::value(&opt.solver.threads)->default_value(opt.solver.threads),
       "threads of the coloured order and of the collision handling (0 = all cores); "
       "results do not depend on it")
      ("solver", po::value(&solver)->default_value(solver),
       "pbd: the paper's energy-as-constraint projection; xpbd: compliant, physical stiffness")
      ("material", po::value(&material)->default_value(material),
       ("membrane material: " + join(material_names())).c_str())
      ("mu", po::value(&opt.material_params.mu)->default_value(opt.material_params.mu),
       "Lame mu (energy per normalized area); in pbd mode only lambda/mu matters")
      ("lambda", po::value(&opt.material_params.lambda)->default_value(opt.material_params.lambda),
       "plane-stress Lame lambda")
      ("c10", po::value(&opt.material_params.c10)->default_value(opt.material_params.c10),
       "Mooney-Rivlin C10")
      ("c01", po::value(&opt.material_params.c01)->default_value(opt.material_params.c01),
       "Mooney-Rivlin C01")
      ("young", po::value(&young), "Young's modulus E (with --thickness): sets mu and lambda")
      ("poisson", po::value(&poisson)->default_value(poisson), "Poisson ratio (with --young)")
      ("thickness", po::value(&thickness), "shell thickness h (with --young)")
      ("bending", po::value(&bending)->default_value(bending),
       "isometric (paper, flat rest) | dihedral (rest-aware) | none")
      ("k-b", po::value(&opt.solver.k_bending)->default_value(opt.solver.k_bending),
       "bending k_B: pbd correction multiplier in [0,1]; xpbd energy scale")
      ("mass", po::value(&mass)->default_value(mass), "area: lumped by rest area; unit: m = 1")
      ("density", po::value(&opt.density)->default_value(opt.density), "areal density rho_A")
      ("damping", po::value(&opt.damping)->default_value(opt.damping),
       "fraction of the velocity removed per step, in [0, 1) (the paper has none)")
      ("stop-volume-ratio", po::value(&opt.stop_volume_ratio)->default_value(0.0),
       "stop when V/V0 falls below this (0 = run all frames)")
      ("aniso", po::value(&aniso)->default_value(aniso),
       ("anisotropic energy on the regions: " + join(aniso_names())).c_str())
      ("regions", po::value(&regions_arg)->default_value(regions_arg),
       "faces that get the anisotropic energy: auto (spherical regions by curvature), a file "
       "(one line per region, 0-based face ids), or none")
      ("k-a", po::value(&opt.anisotropy.kappa_a)->default_value(opt.anisotropy.kappa_a),
       "kappa_A: the inward term is k_A = kappa_A mu_A sqrt(face rest area)")
      ("inward", po::value(&inward)->default_value(inward),
       "inward term on the regions: projection (the paper's k_A, pbd) | force (local extra "
       "pressure --region-pressure) | none")
      ("region-pressure", po::value(&opt.region_pressure)->default_value(opt.region_pressure),
       "P_A, extra pressure on the regions with --inward force (normalized units)")
      ("mu-a", po::value(&opt.material_params.mu_aniso)->default_value(opt.material_params.mu_aniso),
       "anisotropic fibre stiffness mu_A")
      ("fiber-target", po::value(&opt.material_params.fiber_target)->default_value(opt.material_params.fiber_target),
       "active-fiber target stretch gamma in (0, 1]")
      ("fiber", po::value(&fiber)->default_value(fiber),
       "fibre direction: centre (toward the region centre) or X,Y,Z (one direction for all)")
      ("measure-regions", po::bool_switch(&measure_regions),
       "select the regions even without --aniso, to report how far they sink in (summary)")
      ("inversion-aware", po::bool_switch(&opt.solver.inversion_aware),
       "orientation s = sign(n . n_ref) for the anisotropic faces (ARAP then differs from sqrt)")
      ("collisions", po::value(&collisions)->default_value(collisions),
       "on: continuous collision detection and response, the result never passes through "
       "itself; off: faster")
      ("delta", po::value(&opt.collision.delta)->default_value(opt.collision.delta),
       "contact distance (normalized units); closer primitives are pushed apart to 2 delta")
      ("collision-rounds", po::value(&opt.collision.rounds)->default_value(opt.collision.rounds),
       "detection/response rounds per step before the fail-safe")
      ("warm-start", po::value(&warm_start)->default_value(warm_start),
       "on: push along the previous step's contacts before detection (resting contact, fewer "
       "detections); off: every step's contacts come from detection alone")
      ("speculative-broad-phase", po::value(&speculative)->default_value(speculative),
       "on: the collision broad phase starts on predicted positions on a spare thread while "
       "the solve runs, and is completed for the actual ones (the same candidate pairs); off: "
       "it runs after the solve; auto: on with --order sequential (a single-threaded solve), "
       "off with --order coloured (whose solve needs the spare thread). With --threads 1 there "
       "is no spare thread and 'on' only keeps the result equal to that of other thread counts "
       "('off' is faster there)")
      ("validate", po::value(&validate)->default_value(validate),
       "CGAL self-intersection check: off | end | every-frame (exit code 4 if new ones)")
      ("fields", po::value(&fields_prefix),
       "write PREFIX_start.ply and PREFIX_end.ply: per-vertex mean and Gaussian curvature, "
       "pressure load and elastic energy density, coloured by --fields-colour")
      ("fields-colour", po::value(&fields_colour)->default_value(fields_colour),
       "mean | gaussian | pressure | energy: blue-white-red over the 2nd-98th percentile")
      ("log", po::value(&log_path), "per-frame CSV log")
      ("summary", po::value(&summary_path), "JSON summary of the run")
      ("quiet,q", po::bool_switch(&quiet), "no progress on stderr");
  try {
    const po::variables_map vm = parse_command_line(argc, argv, desc, input);
    if (vm.count("help")) {
      std::cout << desc << "\nexit codes: 0 success, 1 bad usage, 2 bad input mesh, "
                           "3 simulation failed (last good state written)\n";
      return 0;
    }
    if (input.empty()) throw UsageError("missing INPUT mesh");
    if (output.empty()) throw UsageError("missing -o OUTPUT");
    opt.solver.kind = parse_solver(solver);
    if (order == "sequential")
      opt.solver.order = ConstraintOrder::Sequential;
    else if (order == "coloured")
      opt.solver.order = ConstraintOrder::Coloured;
    else
      throw UsageError("--order must be sequential or coloured, got '" + order + "'");
    opt.material = parse_material_kind(material);
    opt.bending = parse_bending(bending);
    opt.pressure_model = parse_pressure_model(pressure_model);
    opt.mass = parse_mass(mass);
    opt.solver.aniso = parse_aniso_kind(aniso);
    if (collisions != "on" && collisions != "off")
      throw UsageError("--collisions expects on or off, got '" + collisions + "'");
    opt.collisions = collisions == "on";
    if (warm_start != "on" && warm_start != "off")
      throw UsageError("--warm-start expects on or off, got '" + warm_start + "'");
    opt.collision.warm_start = warm_start == "on";
    if (speculative == "auto")
      opt.speculative_broad_phase = SpeculativeBroadPhase::Auto;
    else if (speculative == "on")
      opt.speculative_broad_phase = SpeculativeBroadPhase::On;
    else if (speculative == "off")
      opt.speculative_broad_phase = SpeculativeBroadPhase::Off;
    else
      throw UsageError("--speculative-broad-phase expects auto, on or off, got '" + speculative +
                       "'");
    opt.collision.threads = opt.solver.threads;
    opt.validate = parse_validate(validate);
    opt.frame_energies = !log_path.empty();  // only the CSV log reports them
    opt.inward_term = parse_inward(inward);
    if (fiber != "centre") {
      opt.anisotropy.fiber_mode = FiberMode::User;
      opt.anisotropy.user_direction = parse_direction(fiber);
    }
    if (vm.count("young") || vm.count("thickness")) {
      if (!vm.count("young") || !vm.count("thickness"))
        throw UsageError("--young needs --thickness (and the other way round)");
      const MaterialParams lame = membrane_lame_from_young(young, poisson, thickness);
      opt.material_params.mu = lame.mu;
      opt.material_params.lambda = lame.lambda;
    }
  } catch (const po::error& e) {
    return usage_error("run", e.what());
  } catch (const UsageError& e) {
    return usage_error("run", e.what());
  }

  try {
    InputReport report;
    const Mesh mesh = read_input_mesh(input, &report);
    for (const std::string& w : report.warnings) std::cerr << "warning: " << w << '\n';
    // Regions: where the anisotropic energy acts (and where its effect is measured).
    if (regions_arg == "auto") {
      if (opt.solver.aniso != AnisoKind::None || measure_regions) {
        RegionReport region_report;
        opt.anisotropy.regions = regions_from_face_ids(
            select_spherical_regions(mesh, positions_from_mesh(mesh), RegionOptions{}, &region_report));
        if (!quiet)
          std::cerr << "regions: " << opt.anisotropy.regions.size()
                    << " spherical regions selected by curvature\n";
      }
    } else if (regions_arg != "none") {
      opt.anisotropy.regions = read_region_file(regions_arg, mesh.number_of_faces());
    }
    Simulator sim(mesh, opt);
    if (sim.rest_report().degenerate_faces > 0)
      std::cerr << "warning: " << sim.rest_report().degenerate_faces
                << " degenerate faces carry no membrane energy; " << sim.rest_report().inactive_hinges
                << " hinges touching them are inactive\n";
    if (sim.rest_report().clamped_cotangents > 0)
      std::cerr << "warning: " << sim.rest_report().clamped_cotangents
                << " rest angles below 1 or above 179 degrees: their bending cotangents were "
                   "clamped to +-cot(1 degree)\n";

    const FieldColour colour = parse_field_colour(fields_colour);
    if (!fields_prefix.empty())
      write_fields_ply(fields_prefix + "_start.ply", sim, sim.positions_in_input_units(),
                       compute_vertex_fields(sim), colour);
    std::string csv = CSV_HEADER;
    const auto start = std::chrono::steady_clock::now();
    auto last_report = start;
    std::string status = "ok";
    std::string failure;
    double min_ratio = 1.0;
    CollisionTotals totals;
    long new_intersections = -1;
    while (!sim.finished()) {
      FrameMetrics m;
      try {
        m = sim.step();
      } catch (const SimulationError& e) {
        status = "failed";
        failure = e.what();
        break;
      }
      min_ratio = std::min(min_ratio, m.volume_ratio);
      totals.add(m);
      if (m.new_intersections >= 0) new_intersections = m.new_intersections;
      if (opt.validate == ValidateMode::EveryFrame && m.new_intersections > 0 && status == "ok") {
        status = "new self-intersections";
        failure = std::to_string(m.new_intersections) + " new self-intersecting face pairs at frame " +
                  std::to_string(m.frame);
      }
      if (!log_path.empty()) csv += csv_row(m);
      const auto now = std::chrono::steady_clock::now();
      if (!quiet && (std::chrono::duration<double>(now - last_report).count() > 1.0 ||
                     sim.finished())) {
        std::cerr << "frame " << m.frame << "/" << opt.frames << "  V/V0 " << std::setprecision(6)
                  << m.volume_ratio << "  " << std::setprecision(3)
                  << std::chrono::duration<double>(now - start).count() << " s\n";
        last_report = now;
      }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    write_mesh_atomic(output, mesh, sim.positions_in_input_units());
    if (!fields_prefix.empty())
      write_fields_ply(fields_prefix + "_end.ply", sim, sim.positions_in_input_units(),
                       compute_vertex_fields(sim), colour);
    if (!log_path.empty()) write_text_atomic(log_path, csv);
    if (!summary_path.empty()) {
      JsonObject options;
      options.add("pressure", opt.pressure).add("pressure_model", pressure_model)
          .add("frames", opt.frames).add("dt", opt.dt).add("iterations", opt.solver.iterations)
          .add("solver", solver).add("order", order).add("threads", opt.solver.threads).add("material", material).add("mu", opt.material_params.mu)
          .add("lambda", opt.material_params.lambda).add("bending", bending)
          .add("k_b", opt.solver.k_bending).add("mass", mass).add("density", opt.density)
          .add("stop_volume_ratio", opt.stop_volume_ratio).add("delta", opt.collision.delta)
          .add("collision_rounds", opt.collision.rounds).add("warm_start", warm_start)
          .add("speculative_broad_phase", speculative);
      JsonObject summary;
      summary.add("status", status).add("failure", failure).add("input", input).add("output", output)
          .add("vertices", report.vertices).add("faces", report.faces)
          .add("components", report.components).add("reoriented", report.reoriented)
          .add("degenerate_faces", sim.rest_report().degenerate_faces)
          .add("normalization_scale", sim.normalization().scale).add("options", options)
          .add("frames_run", sim.frame()).add("final_volume_ratio", sim.volume_ratio())
          .add("min_volume_ratio", min_ratio).add("wall_seconds", seconds)
          .add("mean_step_ms", sim.frame() > 0 ? 1e3 * seconds / sim.frame() : 0.0)
          .add("collisions", opt.collisions).add("excluded_contact_pairs", sim.excluded_contact_pairs())
          .add("new_intersections", static_cast<int>(new_intersections))
          .add("regions", opt.anisotropy.regions.size())
          .add("anisotropic_faces", sim.anisotropy_report().faces)
          .add("region_inward_displacement", sim.region_inward_displacement())
          .add("table2", totals.json(sim.frame()))
          .add("warnings", report.warnings);
      write_text_atomic(summary_path, summary.str() + "\n");
    }
    if (status == "new self-intersections" || (new_intersections > 0 && status == "ok")) {
      std::cerr << "shellcontract run: validation found new self-intersections: "
                << (failure.empty() ? std::to_string(new_intersections) + " face pairs at the end" : failure)
                << '\n';
      return static_cast<int>(ExitCode::NewSelfIntersections);
    }
    if (status != "ok") {
      std::cerr << "shellcontract run: simulation failed: " << failure
                << "\nthe last good state (frame " << sim.frame() << ") was written to " << output << '\n';
      return static_cast<int>(ExitCode::SimulationFailed);
    }
    if (!quiet)
      std::cerr << "wrote " << output << ": " << sim.frame() << " frames, V/V0 = "
                << std::setprecision(6) << sim.volume_ratio() << '\n';
    return 0;
  } catch (const InputError& e) {
    std::cerr << "shellcontract run: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadInput);
  } catch (const UsageError& e) {
    std::cerr << "shellcontract run: " << e.what() << '\n';
    return static_cast<int>(ExitCode::BadUsage);
  }
}

}  // namespace shellcontract::cli
