#include <algorithm>
#include <charconv>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "material/registry.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"
#include "sim/bending_models.hpp"
#include "sim/keyed_options.hpp"
#include "sim/option_builders.hpp"

namespace shellcontract {

std::string shortest_text(double x) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

namespace {

using namespace option_builders;
namespace ranges = option_ranges;

/// A point or direction "X,Y,Z": three decimal numbers (parse_decimal, whatever locale a host
/// program set), blanks allowed around each, as the stream that read them took them.
bool parse_xyz(const std::string& text, Vec3& p) {
  std::size_t begin = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? text.find(',', begin) : text.size();
    if (end == std::string::npos) return false;
    std::string_view field(text.data() + begin, end - begin);
    const auto blank = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
    while (!field.empty() && blank(field.front())) field.remove_prefix(1);
    while (!field.empty() && blank(field.back())) field.remove_suffix(1);
    if (!parse_decimal(field, p[k])) return false;
    begin = end + 1;
  }
  return true;
}

Choices<MaterialKind> material_choices() {
  Choices<MaterialKind> c;
  for (const std::string& n : material_names()) c.emplace_back(n, parse_material_kind(n));
  return c;
}

Choices<AnisoKind> aniso_choices() {
  Choices<AnisoKind> c;
  for (const std::string& n : aniso_names()) c.emplace_back(n, parse_aniso_kind(n));
  return c;
}

/// --region-weights FILE (sim/region_weights.hpp); read when the mesh is known.
OptionSpec region_weights_option() {
  OptionSpec o;
  o.name = "region-weights";
  o.value_name = "FILE";
  o.help =
      "regions and strength from per-vertex weights (a Blender vertex group, a weight map): one "
      "weight in [0, 1] per line in the mesh's vertex order; the faces whose vertices all weigh 0 "
      "stay out, the others sink with --region-shrink times the mean of their vertices' weights; "
      "excludes --regions";
  o.set = [](RunOptions& r, const std::string& v) {
    if (v.empty()) bad("region-weights", v, "a file name");
    r.region_weight_file = v;
  };
  o.get = [](const RunOptions& r) { return r.region_weight_file; };
  o.bad_examples = {""};
  return o;
}

OptionSpec region_option() {
  OptionSpec o;
  o.name = "regions";
  o.value_name = "auto|none|FILE";
  o.help =
      "regions that sink in (the local contraction, --region-shrink): auto (spherical regions "
      "found by curvature), none, or a file with one line per region of 0-based face ids, "
      "optionally after a strength 'S:' in [0, 1] ('0.5: 12 13 14': the share of --region-shrink "
      "that region sinks with; 1 without); a region should be a part of the surface (a file "
      "that lists no region is a warning, one over most of a closed surface can fail the run); "
      "default none, auto with --aniso or --measure-regions";
  o.set = [](RunOptions& r, const std::string& v) {
    if (v.empty()) bad("regions", v, "auto, none or a file name");
    r.regions = v == "auto"   ? RegionSource::Auto
                : v == "none" ? RegionSource::None
                              : RegionSource::File;
    r.region_file = r.regions == RegionSource::File ? v : std::string();
  };
  o.get = [](const RunOptions& r) {
    return r.regions == RegionSource::Auto      ? std::string("auto")
           : r.regions == RegionSource::None    ? std::string("none")
           : r.regions == RegionSource::Weights ? std::string("weights")
                                                : r.region_file;
  };
  o.bad_examples = {""};
  return o;
}

/// --region-at X,Y,Z (repeatable; ';' separates the points of one value, as get() writes them).
OptionSpec region_at_option() {
  OptionSpec o;
  o.name = "region-at";
  o.value_name = "X,Y,Z";
  o.repeatable = true;
  o.help =
      "a region around the surface point nearest to X,Y,Z (repeatable, or X,Y,Z;X,Y,Z): the "
      "spherical cap there, as `regions --region-at` picks it, in the input's coordinates; "
      "excludes --regions and --region-weights. A point farther from the surface than 1.5 % of "
      "the bounding box's diagonal is a warning";
  o.set = [](RunOptions& r, const std::string& v) {
    std::vector<Vec3> points;
    std::size_t begin = 0;
    do {
      const std::size_t end = std::min(v.find(';', begin), v.size());
      const std::string text = v.substr(begin, end - begin);
      Vec3 p;
      if (!parse_xyz(text, p) || !p.allFinite())
        bad("region-at", text,
            "a point X,Y,Z of three finite numbers" +
                std::string(text.size() < v.size() ? " (in '" + v + "', points are separated by ';')" : ""));
      points.push_back(p);
      begin = end + 1;
    } while (begin <= v.size());
    r.region_points = points;
  };
  o.get = [](const RunOptions& r) {
    std::string s;
    for (const Vec3& p : r.region_points)
      s += (s.empty() ? "" : ";") + shortest_text(p.x()) + "," + shortest_text(p.y()) + "," + shortest_text(p.z());
    return s;
  };
  o.bad_examples = {"", "1,2", "1,2,3,4", "a,b,c", "1,2,nan", "1 2 3", "1,2,3;"};
  return o;
}

/// --delta: a number, or auto (the paper's delta, or 1/80 of the mean edge length where that is
/// smaller, or half the smallest rest gap: sim/contact_distance.hpp, which also refuses a number
/// the mesh does not allow; the range here is the mesh-independent one).
OptionSpec delta_option() {
  using R = RunOptions;
  const Interval range = ranges::delta();
  OptionSpec o = number(
      "delta", 0, "DELTA|auto",
      "contact distance (normalized units); closer primitives are pushed apart to 2 delta; auto: "
      "the default, or 1/80 of the mean edge length where smaller (fewer collision pairs per "
      "face on meshes finer than the paper's), and below the smallest gap at rest; a number "
      "above 1/8 of the mean edge (and the default) is refused",
      range, [](R& r) -> double& { return r.sim.collision.delta; });
  const auto set_number = o.set;
  o.set = [set_number](R& r, const std::string& v) {
    if (v == "auto") {
      r.sim.auto_delta = true;
      r.sim.collision.delta = CollisionOptions{}.delta;
      return;
    }
    set_number(r, v);
    r.sim.auto_delta = false;
  };
  const auto get_number = o.get;
  o.get = [get_number](const R& r) {
    return r.sim.auto_delta ? std::string("auto") : get_number(r);
  };
  o.bad_examples.push_back("Auto");
  return o;
}

OptionSpec fiber_option() {
  OptionSpec o;
  o.name = "fiber";
  o.value_name = "centre|X,Y,Z";
  o.help =
      "fibre direction of the regions: centre (toward the region's centre) or one nonzero "
      "direction X,Y,Z";
  o.set = [](RunOptions& r, const std::string& v) {
    AnisotropyOptions& a = r.sim.anisotropy;
    if (v == "centre") {
      a.fiber_mode = FiberMode::TowardCentre;
      return;
    }
    Vec3 d;
    if (!parse_xyz(v, d) || !d.allFinite() || d.cwiseAbs().maxCoeff() == 0.0)
      bad("fiber", v, "'centre' or a nonzero finite direction X,Y,Z");
    a.fiber_mode = FiberMode::User;
    a.user_direction = d;
  };
  o.get = [](const RunOptions& r) {
    const AnisotropyOptions& a = r.sim.anisotropy;
    if (a.fiber_mode == FiberMode::TowardCentre) return std::string("centre");
    return shortest_text(a.user_direction.x()) + "," + shortest_text(a.user_direction.y()) + "," +
           shortest_text(a.user_direction.z());
  };
  o.bad_examples = {"0,0,0", "1,2", "nan,0,0", "up"};
  return o;
}

std::vector<OptionSpec> build_table() {
  using R = RunOptions;
  std::vector<OptionSpec> t;
  // ---- how much it contracts
  t.push_back(
      with_keyframes(number("pressure", 'p', "P",
                            "net outside over-pressure at the rest volume (normalized units; > 0 "
                            "compresses, < 0 inflates)",
                            ranges::pressure(), [](R& r) -> double& { return r.sim.pressure; }),
                     KeyedValue::Pressure));
  t.push_back(number("air-balance", 0, "R",
                     "air inside the shell (isothermal): the V/V0 at which its pressure balances "
                     "the outside pressure, so the shell slows down and stops near R; 0 = no air "
                     "(constant pressure, the paper's)",
                     ranges::air_balance(), [](R& r) -> double& { return r.sim.air_balance; }));
  t.push_back(with_keyframes(
      number("target-volume", 0, "R",
             "drive V/V0 to R and hold it there (a global volume constraint); 0 = off, the "
             "pressure alone decides. Reached when the end's V/V0 is within min(0.005, 5 % "
             "of R) of R, else exit 5",
             ranges::target_volume(), [](R& r) -> double& { return r.sim.target_volume; }),
      KeyedValue::TargetVolume));
  t.push_back(integer("target-ramp", 0, "N",
                      "frames over which the target volume (and the regions' shrink, --inward "
                      "volume) is approached, at most half of --frames",
                      ranges::TARGET_RAMP, [](R& r) -> int& { return r.sim.target_ramp_frames; }));
  t.push_back(number(
      "stop-volume-ratio", 0, "E", "stop at the frame where V/V0 reaches E (0 = run all frames)",
      ranges::stop_volume_ratio(), [](R& r) -> double& { return r.sim.stop_volume_ratio; }));
  t.push_back(integer("frames", 'n', "N", "number of time steps", ranges::FRAMES,
                      [](R& r) -> int& { return r.sim.frames; }));
  t.push_back(choice("pressure-model",
                     "energy: f = -P dV/dx (no net force); paper: P * area * unit vertex normal",
                     Choices<PressureModel>{{"energy", PressureModel::EnergyConsistent},
                                            {"paper", PressureModel::Paper}},
                     [](R& r) -> PressureModel& { return r.sim.pressure_model; }));
  // ---- solver
  t.push_back(number("dt", 0, "DT", "time step (normalized units)", ranges::dt(),
                     [](R& r) -> double& { return r.sim.dt; }));
  t.push_back(integer("iterations", 0, "N", "Gauss-Seidel sweeps per step (paper: 5)",
                      ranges::ITERATIONS, [](R& r) -> int& { return r.sim.solver.iterations; }));
  t.push_back(choice(
      "solver",
      "xpbd: compliant, physical stiffness (the shell material of --young and --thickness, the "
      "same at any resolution and time step once the sweeps converge: a stiffer material or a "
      "finer mesh needs more --iterations); pbd: the paper's "
      "energy-as-constraint projection (membrane --mu and --lambda, damping 0.2)",
      Choices<SolverKind>{{"pbd", SolverKind::Pbd}, {"xpbd", SolverKind::Xpbd}},
      [](R& r) -> SolverKind& { return r.sim.solver.kind; }));
  t.push_back(choice("order",
                     "sequential: one fixed Gauss-Seidel order, input order (the paper names "
                     "no order), one thread; coloured: parallel by colour, "
                     "bit-identical for any thread count, the faster at equal accuracy; auto: "
                     "coloured",
                     Choices<OrderChoice>{{"auto", OrderChoice::Auto},
                                          {"sequential", OrderChoice::Sequential},
                                          {"coloured", OrderChoice::Coloured}},
                     [](R& r) -> OrderChoice& { return r.order; }));
  t.push_back(
      integer("threads", 0, "N",
              "threads of the coloured order and of the collision handling (0 = the CPUs this "
              "process may use: its affinity, held to its cgroup's CPU quota); results do not "
              "depend on it",
              ranges::THREADS, [](R& r) -> int& { return r.sim.solver.threads; }));
  t.push_back(number("damping", 0, "D",
                     "fraction of the velocity removed per step (the paper has none); 0.2 under "
                     "--solver pbd unless given",
                     ranges::damping(), [](R& r) -> double& { return r.sim.damping; }));
  // ---- material
  t.push_back(choice("material", "membrane material", material_choices(),
                     [](R& r) -> MaterialKind& { return r.sim.material; }));
  t.push_back(number("mu", 0, "MU",
                     "Lame mu (energy per normalized area); in pbd mode only lambda/mu matters; "
                     "under xpbd, unless given, --young and --thickness set it",
                     ranges::mu(), [](R& r) -> double& { return r.sim.material_params.mu; }));
  // Negative down to -mu, as a negative --poisson gives it (lambda = E h nu / (1 - nu^2)): the
  // membrane energy mu tr E^2 + lambda/2 tr^2 E is positive definite for mu > 0 and mu + lambda
  // > 0, which check_sim_options holds (the range of one option cannot name the other's value).
  t.push_back(number("lambda", 0, "LAMBDA",
                     "plane-stress Lame lambda (as --mu); negative for a negative Poisson ratio, "
                     "down to (not at) -mu",
                     ranges::lambda(),
                     [](R& r) -> double& { return r.sim.material_params.lambda; }));
  t.push_back(number("c10", 0, "C10", "Mooney-Rivlin C10", ranges::c10(),
                     [](R& r) -> double& { return r.sim.material_params.c10; }));
  t.push_back(number("c01", 0, "C01", "Mooney-Rivlin C01", ranges::c01(),
                     [](R& r) -> double& { return r.sim.material_params.c01; }));
  t.push_back(optional_number("young", "E",
                              "Young's modulus (with --thickness): sets mu and lambda, and with "
                              "--solver xpbd and dihedral bending also k_B (unless --k-b is "
                              "given): E h^3 / (36 (1 - nu^2)). The default shell material "
                              "applies under xpbd unless --mu or --lambda is given or --material "
                              "is mooney-rivlin",
                              positive(),
                              [](R& r) -> std::optional<double>& { return r.young; }));
  t.push_back(number("poisson", 0, "NU", "Poisson ratio (with --young)",
                     between(-1.0, 0.5, true, true), [](R& r) -> double& { return r.poisson; }));
  t.push_back(optional_number("thickness", "H", "shell thickness (with --young; normalized units)",
                              positive(),
                              [](R& r) -> std::optional<double>& { return r.thickness; }));
  t.push_back(described_choice("bending", "the bending energy", bending_models(),
                               [](R& r) -> BendingModel& { return r.sim.bending; }));
  t.push_back(number("k-b", 0, "KB",
                     "bending k_B: pbd correction multiplier (at most 1); xpbd energy scale "
                     "(unless given, from --young and --thickness)",
                     ranges::k_b(), [](R& r) -> double& { return r.sim.solver.k_bending; }));
  t.push_back(choice("mass", "area: lumped by rest area; unit: m = 1",
                     Choices<MassModel>{{"area", MassModel::AreaLumped}, {"unit", MassModel::Unit}},
                     [](R& r) -> MassModel& { return r.sim.mass; }));
  t.push_back(number("density", 0, "RHO", "areal density rho_A", ranges::density(),
                     [](R& r) -> double& { return r.sim.density; }));
  // ---- local contraction
  t.push_back(choice("aniso", "anisotropic energy on the regions", aniso_choices(),
                     [](R& r) -> AnisoKind& { return r.sim.solver.aniso; }));
  t.push_back(region_option());
  t.push_back(region_weights_option());
  t.push_back(region_at_option());
  t.push_back(number("k-a", 0, "KAPPA",
                     "kappa_A: the inward term is k_A = kappa_A mu_A sqrt(face rest area)",
                     ranges::k_a(), [](R& r) -> double& { return r.sim.anisotropy.kappa_a; }));
  // Described choices: the values and their descriptions in one list (a plain choice's help
  // listed the values again after the text that described them).
  t.push_back(described_choice(
      "inward", "how the regions are made to sink in",
      std::vector<option_builders::DescribedChoice<InwardTerm>>{
          {"volume", InwardTerm::Volume,
           "each region sinks a dimple around its apex holding S of its rest cap volume, S = "
           "--region-shrink, towards the dimple's mirror image and holds it there; under -p > 0 "
           "without --target-volume the regions also take an extra pressure 2 S P"},
          {"force", InwardTerm::Force,
           "an extra pressure on the regions, P_A = 10 S, without net force or torque: this "
           "tool's replacement for the paper's k_A"},
          {"projection", InwardTerm::Projection,
           "the paper's k_A inside the E_A projection; --aniso, pbd"},
          {"none", InwardTerm::None, ""}},
      [](R& r) -> InwardTerm& { return r.sim.inward_term; }));
  t.push_back(described_choice(
      "dimple", "the shape --inward volume sinks a region to",
      std::vector<option_builders::DescribedChoice<DimpleShape>>{
          {"mirror", DimpleShape::Mirror,
           "default: the cap mirrored through its rim's plane, an isometry, carried by the shell "
           "away from the regions, the ring at the rim left to the solver; a region whose rim "
           "lies far off any plane sinks only its part above a plane cut; volume where a region "
           "has no mirror: a collinear rim or no interior vertex"},
          {"volume", DimpleShape::Volume, "the dimple's cap volume is projected, its shape free"}},
      [](R& r) -> DimpleShape& { return r.sim.dimple_shape; }));
  t.push_back(number("region-max-area", 0, "F",
                     "--regions auto: drop regions larger than this fraction of the surface "
                     "(0.05 keeps bear's head out, which deflates the whole shell)",
                     between(0.0, 1.0, true, false),
                     [](R& r) -> double& { return r.region_max_area; }));
  t.push_back(number("region-shrink", 0, "S",
                     "how much the regions of --regions shrink (the local contraction's "
                     "strength): the share of each region's rest cap volume, around its apex, "
                     "that sinks as a dimple to its mirror image, 0 not at all, 1 the whole "
                     "region; the image takes 2S of the cap volume off (0.5 all of it) only "
                     "where the dimple's rim is flat: a region of few faces mostly loses less",
                     ranges::region_shrink(), [](R& r) -> double& { return r.sim.region_shrink; }));
  t.push_back(number("mu-a", 0, "MUA", "anisotropic fibre stiffness mu_A", ranges::mu_a(),
                     [](R& r) -> double& { return r.sim.material_params.mu_aniso; }));
  t.push_back(number("fiber-target", 0, "GAMMA", "active-fibre target stretch gamma",
                     ranges::fiber_target(),
                     [](R& r) -> double& { return r.sim.material_params.fiber_target; }));
  t.push_back(fiber_option());
  t.push_back(
      flag("measure-regions",
           "report how far the regions sink in (summary); without --regions, --region-weights, "
           "--region-at or --aniso it selects --regions auto and contracts nothing (--inward "
           "none: the baseline run); with one of them the regions are contracted as usual",
           [](R& r) -> bool& { return r.measure_regions; }));
  t.push_back(flag("inversion-aware", "orientation s = sign(n . n_ref) for the anisotropic faces",
                   [](R& r) -> bool& { return r.sim.solver.inversion_aware; }));
  // ---- collisions and validation
  t.push_back(
      on_off_option("collisions",
                    "on: continuous collision detection and response, the result never passes "
                    "through itself; off: faster",
                    [](R& r) -> bool& { return r.sim.collisions; }));
  t.push_back(delta_option());
  t.push_back(
      integer("collision-rounds", 0, "N", "detection/response rounds per step before the fail-safe",
              ranges::COLLISION_ROUNDS, [](R& r) -> int& { return r.sim.collision.rounds; }));
  t.push_back(on_off_option(
      "warm-start",
      "on: push along the previous step's contacts before detection (resting contact); "
      "off: every step's contacts come from detection alone",
      [](R& r) -> bool& { return r.sim.collision.warm_start; }));
  t.push_back(
      choice("speculative-broad-phase",
             "on: the broad phase starts on predicted positions on a spare thread while the solve "
             "runs (the same candidate pairs); off: after the solve; auto: on with --order "
             "sequential, off with --order coloured",
             Choices<SpeculativeBroadPhase>{{"auto", SpeculativeBroadPhase::Auto},
                                            {"on", SpeculativeBroadPhase::On},
                                            {"off", SpeculativeBroadPhase::Off}},
             [](R& r) -> SpeculativeBroadPhase& { return r.sim.speculative_broad_phase; }));
  t.push_back(choice(
      "validate", "CGAL self-intersection check of the result (exit code 4 if it finds new ones)",
      Choices<ValidateMode>{{"off", ValidateMode::Off},
                            {"end", ValidateMode::End},
                            {"every-frame", ValidateMode::EveryFrame}},
      [](R& r) -> ValidateMode& { return r.sim.validate; }));
  // Every setter also records that the option was given (RunOptions::given, by field).
  for (OptionSpec& o : t) {
    auto parse = o.set;
    const std::string name = option_field(o.name);
    o.set = [parse, name](RunOptions& r, const std::string& v) {
      parse(r, v);
      r.given.insert(name);
    };
  }
  return t;
}

std::string dashes(std::string name) {
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}

}  // namespace

const std::vector<OptionSpec>& run_option_table() {
  static const std::vector<OptionSpec> table = build_table();
  return table;
}

const OptionSpec* find_run_option(const std::string& name) {
  const std::string key = dashes(name);
  for (const OptionSpec& o : run_option_table())
    if (o.name == key) return &o;
  return nullptr;
}

void set_run_option(RunOptions& options, const std::string& name, const std::string& value) {
  const OptionSpec* o = find_run_option(name);
  if (!o) throw UsageError("unknown option '" + name + "'");
  o->set(options, value);
}

}  // namespace shellcontract

namespace shellcontract {

std::string option_field(const std::string& name) {
  std::string field = name;
  for (char& c : field)
    if (c == '-') c = '_';
  return field;
}

std::string option_name(const OptionSpec& option, OptionSpelling spelling) {
  return spelling == OptionSpelling::Cli ? option.name : option_field(option.name);
}

std::string spell_options(const std::string& message, OptionSpelling spelling) {
  std::string out;
  std::size_t i = 0;
  while (i < message.size()) {
    const std::size_t open = message.find('`', i);
    const std::size_t close = open == std::string::npos ? open : message.find('`', open + 1);
    if (close == std::string::npos) break;
    const std::string field = message.substr(open + 1, close - open - 1);
    const OptionSpec* o = field.find('-') == std::string::npos ? find_run_option(field) : nullptr;
    // The region finders' options (`regions` and regions()), which no run option shares.
    const bool region = !o && std::find(REGION_OPTION_FIELDS.begin(), REGION_OPTION_FIELDS.end(),
                                        field) != REGION_OPTION_FIELDS.end();
    out += message.substr(i, open - i);
    if (o)
      out += spelling == OptionSpelling::Cli ? "--" + o->name : option_field(o->name);
    else if (region && spelling == OptionSpelling::Cli) {
      std::string flag = field;
      std::replace(flag.begin(), flag.end(), '_', '-');
      out += "--" + flag;
    } else if (region)
      out += field;
    else
      out += message.substr(open, close - open + 1);
    i = close + 1;
  }
  return out + message.substr(std::min(i, message.size()));
}

}  // namespace shellcontract
