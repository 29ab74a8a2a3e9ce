#include "traverse/scene/scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "traverse/core/types.hpp"

namespace traverse::scene {

namespace {

using Teuchos::ParameterList;

// ---------------------------------------------------------------------------------------
// Registries
// ---------------------------------------------------------------------------------------
std::shared_ptr<TypeRegistry> section_types() {
  auto r = std::make_shared<TypeRegistry>("cross-section");
  r->add({"solid_circle", "Solid circular section: A = pi r^2, I = pi r^4 / 4",
          {real("radius", "Section radius", "m").positive().required()}, {}});
  r->add({"hollow_circle", "Hollow circular (tube) section: A = pi (ro^2 - ri^2), I = pi (ro^4 - ri^4) / 4",
          {real("outer_radius", "Outer radius", "m").positive().required(),
           real("inner_radius", "Inner radius", "m").non_negative().required()},
          {[](const ParameterList& s, const CheckContext& ctx) {
            if (s.get<double>("inner_radius") >= s.get<double>("outer_radius"))
              ctx.fail("inner_radius", "an inner radius smaller than outer_radius = " +
                       format_number(s.get<double>("outer_radius")),
                       format_number(s.get<double>("inner_radius")));
          }}});
  r->add({"rectangle", "Rectangular section bending about its width axis: A = b h, I = b h^3 / 12",
          {real("width", "Width b (out of the bending plane)", "m").positive().required(),
           real("height", "Height h (in the bending plane)", "m").positive().required()}, {}});
  r->add({"properties", "Section given by its properties directly",
          {real("area", "Cross-section area A", "m^2").positive().required(),
           real("second_moment", "Second moment of area I about the bending axis", "m^4").positive().required()}, {}});
  return r;
}

Check one_of_two(const std::string& a, const std::string& b) {
  return [a, b](const ParameterList& s, const CheckContext& ctx) {
    const bool ha = s.isParameter(a), hb = s.isParameter(b);
    if (ha == hb)
      ctx.fail(ha ? b : "", "exactly one of '" + a + "' and '" + b + "'", ha ? "both" : "neither");
  };
}

std::vector<Param> motion_params() {
  return {real("speed", "Speed when the load enters the structure", "m/s").non_negative().required(),
          real("acceleration", "Constant acceleration along the direction of travel", "m/s^2").def(0.0),
          choice("entry", "End the load enters at: left (x = 0, travels towards +x) or right (x = L, towards -x)",
                 {"left", "right"}).def("left"),
          real("entry_time", "Time at which the load enters", "s").non_negative().def(0.0)};
}

Check moves(const std::string& type) {
  return [type](const ParameterList& s, const CheckContext& ctx) {
    if (s.get<double>("speed") <= 0.0 && s.get<double>("acceleration") <= 0.0)
      ctx.fail("speed", "a " + type + " that moves (speed > 0, or acceleration > 0)",
               "speed 0 and acceleration " + format_number(s.get<double>("acceleration")));
  };
}

std::shared_ptr<TypeRegistry> load_types() {
  auto r = std::make_shared<TypeRegistry>("load");
  {
    TypeInfo t{"moving_mass",
               "A point mass riding on the structure: its weight plus its inertia (with the centrifugal, "
               "Coriolis and acceleration terms)",
               {real("mass", "Mass M", "kg").positive(),
                real("mass_fraction", "Mass as a fraction p of beam + mass: M = p/(1-p) * beam mass", "")
                    .positive()
                    .below(1.0)},
               {one_of_two("mass", "mass_fraction"), moves("moving mass")}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r->add(t);
  }
  {
    TypeInfo t{"moving_force",
               "A downward point force without inertia (the classic moving-load idealisation)",
               {real("force", "Force magnitude, acting along -j", "N").positive(),
                real("mass", "Give the force as the weight M g of this mass", "kg").positive(),
                real("mass_fraction", "Force as the weight of a mass given as a fraction of beam + mass", "")
                    .positive()
                    .below(1.0)},
               {[](const ParameterList& s, const CheckContext& ctx) {
                  const int n = s.isParameter("force") + s.isParameter("mass") + s.isParameter("mass_fraction");
                  if (n != 1)
                    ctx.fail("", "exactly one of 'force', 'mass' and 'mass_fraction'",
                             n == 0 ? "none" : format_number(n) + " of them");
                },
                moves("moving force")}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r->add(t);
  }
  return r;
}

std::shared_ptr<TypeRegistry> probe_types() {
  auto r = std::make_shared<TypeRegistry>("probe");
  r->add({"deflection", "Transverse deflection w (positive up) at a fixed point, as a time series [m]",
          {real("at", "Position along the structure", "m").non_negative().required()}, {}});
  return r;
}

Param build_schema() {
  Param root = section("", "traverse scene");
  root.add(choice("model", "Which structural model to run", {"beam"}).required());
  root.add(text("title", "Free text describing the scene").def("''"));
  root.add(real("gravity", "Gravitational acceleration g, acting along -j", "m/s^2").non_negative().def(constants::standard_gravity));

  Param beam = section("beam", "Small-deflection Euler–Bernoulli beam (model: beam)");
  beam.add(real("length", "Beam length L", "m").positive().required());
  beam.add(real("youngs_modulus", "Young's modulus E", "Pa").positive().required());
  beam.add(real("density", "Material density rho", "kg/m^3").positive().required());
  beam.add(typed("section", "Cross-section", section_types()).required());
  beam.add(choice("supports", "End conditions at x = 0 and x = L",
                  {"simply-supported", "clamped-free", "clamped-clamped", "clamped-pinned"}).required());
  beam.add(integer("modes", "Number of Galerkin modes (the beam's own eigenmodes)").at_least(1).at_most(200).def(3.0));
  beam.add(integer("quadrature_points", "Gauss points per mesh cell for the Galerkin integrals").at_least(1).at_most(20).def(6.0));
  root.add(beam);

  Param mesh = section("mesh", "Nodes along the structure (uniform spacing): give nodes or ds");
  mesh.add(integer("nodes", "Number of nodes N + 1").at_least(2));
  mesh.add(real("ds", "Node spacing (the length must be a whole number of spacings)", "m").positive());
  mesh.check([](const ParameterList& s, const CheckContext& ctx) {
    if (s.isParameter("nodes") && s.isParameter("ds"))
      ctx.fail("ds", "either 'nodes' or 'ds', not both", "both");
  });
  root.add(mesh);

  root.add(collection("loads", "Moving loads, each under a name of your choice", load_types()));

  Param time = section("time", "Time integration");
  time.add(choice("integrator", "rk4: classical 4th-order Runge–Kutta (reference); newmark: average-acceleration "
                                "Newmark, unconditionally stable, 2nd order", {"rk4", "newmark"}).def("rk4"));
  time.add(real("dt", "Time step; auto: a twentieth of the period of the highest mode, and no more than "
                      "the time a load needs to cross one mesh cell", "s").positive().allow_auto().def("auto"));
  time.add(real("end", "End time; auto: when the last load leaves the structure", "s").positive().allow_auto().def("auto"));
  root.add(time);

  Param out = section("output", "What is written, and where");
  out.add(text("file", "HDF5 output file; auto: the scene file's name with .h5, in the working directory "
                       "(the command line's -o wins)").def("auto"));
  out.add(integer("every", "Write every this many time steps (the first and last states are always written)").at_least(1).def(1.0));
  out.add(collection("probes", "Time series of chosen quantities, each under a name of your choice", probe_types()));
  out.add(word_list("fields", "Fields written at every mesh node at each output step",
                    {"deflection", "slope", "bending_moment"}).def("[]"));
  root.add(out);

  root.check([](const ParameterList& s, const CheckContext& ctx) {
    const double length = s.sublist("beam").get<double>("length");
    const auto& probes = s.sublist("output").sublist("probes");
    for (auto it = probes.begin(); it != probes.end(); ++it) {
      const double at = probes.sublist(probes.name(it)).get<double>("at");
      if (at > length)
        CheckContext(ctx).fail("output.probes." + probes.name(it) + ".at",
                               "a position on the beam, in [0, " + format_number(length) + "]", format_number(at));
    }
    const auto& mesh = s.sublist("mesh");
    if (mesh.isParameter("ds")) {
      const double ds = mesh.get<double>("ds");
      const double cells = length / ds;
      if (std::abs(cells - std::round(cells)) > 1e-9 * std::max(1.0, cells) || std::round(cells) < 1.0)
        ctx.fail("mesh.ds", "a spacing that divides beam.length = " + format_number(length) + " into whole cells",
                 format_number(ds) + " (" + format_number(cells) + " cells)");
    }
  });
  return root;
}

MovingLoadSpec build_load(const std::string& name, const ParameterList& l, double beam_mass, double g) {
  MovingLoadSpec m;
  m.name = name;
  m.type = l.get<std::string>("type");
  m.inertia = m.type == "moving_mass";
  if (m.type != "moving_mass" && m.type != "moving_force") throw std::logic_error("build_load: unknown load type " + m.type);
  if (l.isParameter("mass")) m.mass = l.get<double>("mass");
  if (l.isParameter("mass_fraction")) {
    const double p = l.get<double>("mass_fraction");
    m.mass = p / (1.0 - p) * beam_mass;
  }
  m.force = l.isParameter("force") ? l.get<double>("force") : m.mass * g;
  m.speed = l.get<double>("speed");
  m.acceleration = l.get<double>("acceleration");
  m.entry = l.get<std::string>("entry");
  m.entry_time = l.get<double>("entry_time");
  return m;
}

SectionSpec build_section(const ParameterList& s) {
  SectionSpec out;
  out.shape = s.get<std::string>("type");
  const double pi = constants::pi;
  if (out.shape == "solid_circle") {
    const double r = s.get<double>("radius");
    out.area = pi * r * r;
    out.second_moment = pi * std::pow(r, 4) / 4.0;
  } else if (out.shape == "hollow_circle") {
    const double ro = s.get<double>("outer_radius"), ri = s.get<double>("inner_radius");
    out.area = pi * (ro * ro - ri * ri);
    out.second_moment = pi * (std::pow(ro, 4) - std::pow(ri, 4)) / 4.0;
  } else if (out.shape == "rectangle") {
    const double b = s.get<double>("width"), h = s.get<double>("height");
    out.area = b * h;
    out.second_moment = b * h * h * h / 12.0;
  } else if (out.shape == "properties") {
    out.area = s.get<double>("area");
    out.second_moment = s.get<double>("second_moment");
  } else {
    throw std::logic_error("build_section: unknown section type " + out.shape);
  }
  return out;
}

}  // namespace

const Param& scene_schema() {
  static const Param root = build_schema();
  return root;
}

Scene parse_scene(const std::string& yaml_text, const std::string& file_name, const std::vector<std::string>& overrides) {
  Scene sc;
  sc.file = file_name;
  sc.tree = validate_yaml(yaml_text, file_name, overrides, scene_schema());
  const ParameterList& p = sc.tree.params;
  const std::string model = p.get<std::string>("model");
  if (model == "beam") {
    sc.model = Model::Beam;
  } else {
    throw std::logic_error("parse_scene: unknown model " + model);
  }
  sc.title = p.get<std::string>("title");
  sc.gravity = p.get<double>("gravity");

  const auto& b = p.sublist("beam");
  sc.beam.length = b.get<double>("length");
  sc.beam.youngs_modulus = b.get<double>("youngs_modulus");
  sc.beam.density = b.get<double>("density");
  sc.beam.section = build_section(b.sublist("section"));
  sc.beam.supports = b.get<std::string>("supports");
  sc.beam.modes = b.get<int>("modes");
  sc.beam.quadrature_points = b.get<int>("quadrature_points");

  const auto& m = p.sublist("mesh");
  if (m.isParameter("ds")) {
    sc.mesh.ds = m.get<double>("ds");
    sc.mesh.nodes = static_cast<int>(std::lround(sc.beam.length / sc.mesh.ds)) + 1;
  } else {
    sc.mesh.nodes = m.isParameter("nodes") ? m.get<int>("nodes") : 101;
  }
  sc.mesh.ds = sc.beam.length / (sc.mesh.nodes - 1);

  const auto& loads = p.sublist("loads");
  for (auto it = loads.begin(); it != loads.end(); ++it)
    sc.loads.push_back(build_load(loads.name(it), loads.sublist(loads.name(it)), sc.beam.mass(), sc.gravity));

  const auto& t = p.sublist("time");
  sc.time.integrator = t.get<std::string>("integrator");
  sc.time.dt_auto = t.isType<std::string>("dt");
  if (!sc.time.dt_auto) sc.time.dt = t.get<double>("dt");
  sc.time.end_auto = t.isType<std::string>("end");
  if (!sc.time.end_auto) sc.time.end = t.get<double>("end");
  if (sc.time.end_auto && sc.loads.empty())
    CheckContext(file_name, "", &sc.tree.marks)
        .fail("time.end", "a number when the scene has no loads ('auto' ends when the last load leaves)", "auto");

  const auto& o = p.sublist("output");
  sc.output.file = o.get<std::string>("file");
  if (sc.output.file == "auto") sc.output.file = std::filesystem::path(file_name).stem().string() + ".h5";
  sc.output.every = o.get<int>("every");
  const auto& probes = o.sublist("probes");
  for (auto it = probes.begin(); it != probes.end(); ++it) {
    const auto& pr = probes.sublist(probes.name(it));
    sc.output.probes.push_back({probes.name(it), pr.get<std::string>("type"), pr.get<double>("at")});
  }
  const auto fields = o.get<Teuchos::Array<std::string>>("fields");
  sc.output.fields.assign(fields.begin(), fields.end());

  sc.text = describe(sc.tree, scene_schema(), false);
  return sc;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": expected a readable scene file, found " +
                            (std::filesystem::exists(path) ? "a file that cannot be read" : "no such file"));
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path, overrides);
}

std::string describe_scene(const Scene& scene, bool with_comments) {
  return describe(scene.tree, scene_schema(), with_comments);
}

std::string describe_types() {
  std::ostringstream os;
  for (const auto& reg : {section_types(), load_types(), probe_types()}) {
    os << "# " << reg->category() << " types\n";
    for (const auto& n : reg->names()) {
      const TypeInfo* t = reg->find(n);
      os << "#   " << n << ": " << t->doc << "\n";
      for (const auto& p : t->params) {
        os << "#     " << p.name << ": " << p.doc;
        if (!p.units.empty()) os << " [" << p.units << "]";
        const auto r = p.range_text();
        if (!r.empty()) os << "; " << r;
        if (p.default_text) os << "; default " << *p.default_text;
        else if (p.is_required) os << "; required";
        os << "\n";
      }
    }
  }
  return os.str();
}

}  // namespace traverse::scene
