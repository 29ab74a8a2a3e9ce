#include "traverse/scene/scene.hpp"

#include <Teuchos_ParameterList.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace traverse::scene {

// The words of every enumeration, in enumerator order (the schema's choice lists below).
#define TRAVERSE_ENUM_NAMES(E, ...)                                  \
  template <>                                                        \
  const std::vector<std::string>& enum_names<E>() {                  \
    static const std::vector<std::string> names{__VA_ARGS__};        \
    return names;                                                    \
  }
TRAVERSE_ENUM_NAMES(Supports, "simply-supported", "clamped-free", "clamped-clamped", "clamped-pinned")
TRAVERSE_ENUM_NAMES(BeamIntegrator, "rk4", "newmark")
TRAVERSE_ENUM_NAMES(LoadType, "moving_mass", "moving_force", "coupled_mass", "sprung_mass", "vehicle", "axle_train")
TRAVERSE_ENUM_NAMES(Contact, "bilateral", "unilateral")
TRAVERSE_ENUM_NAMES(ResistanceThrough, "air", "structure")
TRAVERSE_ENUM_NAMES(Entry, "left", "right")
TRAVERSE_ENUM_NAMES(PlanarMode, "auto", "on", "off")
TRAVERSE_ENUM_NAMES(InitialStateType, "static", "rest", "file", "arch")
TRAVERSE_ENUM_NAMES(ContinuationParameter, "end_load", "end_position", "gravity_factor", "load_position",
                    "load_magnitude")
TRAVERSE_ENUM_NAMES(ContinuationMethod, "arclength", "natural")
TRAVERSE_ENUM_NAMES(ContinuationProbeType, "point", "end_compression")
TRAVERSE_ENUM_NAMES(ProbeType, "deflection", "point", "acceleration")
TRAVERSE_ENUM_NAMES(Quantity, "position", "u", "omega", "kappa", "n", "m", "d1", "d2", "d3", "v")
TRAVERSE_ENUM_NAMES(Frame, "fixed", "body")
TRAVERSE_ENUM_NAMES(RodStrain, "inextensible", "extensible", "shearable")
TRAVERSE_ENUM_NAMES(Field, "u", "omega", "kappa", "n", "m", "r", "R", "deflection", "slope", "bending_moment", "v",
                    "stretch", "axial_force")
#undef TRAVERSE_ENUM_NAMES

template <>
const std::vector<std::string>& enum_names<EndType>() {  // the words of end_type_declarations()
  static const std::vector<std::string> names = [] {
    std::vector<std::string> w;
    for (const auto& d : end_type_declarations()) {
      if (static_cast<std::size_t>(d.type) != w.size())
        throw std::logic_error("end_type_declarations: not in enumerator order at " + std::string(d.word));
      w.push_back(d.word);
    }
    return w;
  }();
  return names;
}

namespace {

using Teuchos::ParameterList;

// A list key of the validated scene (validation stores lists as Teuchos::Array).
std::vector<double> numbers(const ParameterList& p, const std::string& key) {
  return p.get<Teuchos::Array<double>>(key).toVector();
}
std::vector<std::string> words(const ParameterList& p, const std::string& key) {
  return p.get<Teuchos::Array<std::string>>(key).toVector();
}

const char* kBeam = "beam";
const char* kRod = "rod";

// ---------------------------------------------------------------------------------------
// Registries
// ---------------------------------------------------------------------------------------
std::shared_ptr<TypeRegistry> section_types() {
  auto r = std::make_shared<TypeRegistry>("cross-section");
  r->add({"solid_circle", "Solid circular section: A = pi r^2, I1 = I2 = pi r^4 / 4, J = pi r^4 / 2",
          {real("radius", "Section radius", "m").positive().required()}, {}});
  r->add({"hollow_circle", "Tube: A = pi (ro^2 - ri^2), I1 = I2 = pi (ro^4 - ri^4) / 4, J = 2 I1",
          {real("outer_radius", "Outer radius", "m").positive().required(),
           real("inner_radius", "Inner radius", "m").non_negative().required()},
          {[](const ParameterList& s, const CheckContext& ctx) {
            if (s.get<double>("inner_radius") >= s.get<double>("outer_radius"))
              ctx.fail("inner_radius", "an inner radius smaller than outer_radius = " +
                       format_number(s.get<double>("outer_radius")),
                       format_number(s.get<double>("inner_radius")));
          }}});
  r->add({"rectangle",
          "Rectangle, width b along d1 (i) and height h along d2 (j): A = b h, I1 = b h^3 / 12, "
          "I2 = h b^3 / 12, J from the thin-walled series for a rectangle",
          {real("width", "Width b along d1", "m").positive().required(),
           real("height", "Height h along d2 (the bending plane of the beam and the rod's initial plane)", "m")
               .positive()
               .required()}, {}});
  r->add({"properties", "Section given by its properties",
          {real("area", "Cross-section area A", "m^2").positive().required(),
           real("second_moment", "Second moment of area I1 (bending in the (j, k) plane)", "m^4").positive().required(),
           real("second_moment_2", "Second moment I2 (out-of-plane bending; default: equal to I1)", "m^4").positive(),
           real("torsion_constant", "Torsion constant J (default: I1 + I2)", "m^4").positive()}, {}});
  return r;
}

std::vector<Param> motion_params() {
  return {real("speed", "Speed at entry_time along the direction of travel", "m/s").non_negative().required(),
          real("acceleration", "Constant acceleration along the direction of travel", "m/s^2").def(0.0),
          choice("entry", "End the load comes from: left (travels towards +s) or right (towards -s)",
                 enum_names<Entry>()).def("left"),
          real("start", "Position at entry_time (default: the entry end)", "m").non_negative(),
          real("entry_time", "Time at which the load starts moving from `start`", "s").non_negative().def(0.0)};
}

Check moves(const std::string& type) {
  return [type](const ParameterList& s, const CheckContext& ctx) {
    if (s.get<double>("speed") <= 0.0 && s.get<double>("acceleration") <= 0.0)
      ctx.fail("speed", "a " + type + " that moves (speed > 0, or acceleration > 0)",
               "speed 0 and acceleration " + format_number(s.get<double>("acceleration")));
  };
}

Check exactly_one(std::vector<std::string> keys) {
  return [keys](const ParameterList& s, const CheckContext& ctx) {
    int n = 0;
    std::string names, last;
    for (size_t i = 0; i < keys.size(); ++i) {
      names += (i ? (i + 1 == keys.size() ? " and '" : ", '") : "'") + keys[i] + "'";
      if (s.isParameter(keys[i])) {
        ++n;
        last = keys[i];
      }
    }
    if (n != 1)
      ctx.fail(n > 1 ? last : "", "exactly one of " + names,
               n == 0 ? "none" : (n == 2 && keys.size() == 2 ? "both" : std::to_string(n) + " of them"));
  };
}

// A list key of a vehicle: empty, one value (for every axle) or one per axle.
Check per_axle(const std::string& key, const std::string& axes_key) {
  return [key, axes_key](const ParameterList& s, const CheckContext& ctx) {
    if (!s.isParameter(key)) return;
    const std::size_t n = numbers(s, axes_key).size(), k = numbers(s, key).size();
    if (k != 1 && k != n)
      ctx.fail(key, "one value (for every axle) or one per axle (" + std::to_string(n) + " in " + axes_key + ")",
               std::to_string(k) + " values");
  };
}

void add_vehicle_types(TypeRegistry& r) {
  const Param contact = choice("contact", "bilateral: the wheels stay on the structure; unilateral: a contact force "
                                          "that would pull ends the run (the event lift_off)",
                               enum_names<Contact>()).def("bilateral");
  {
    TypeInfo t{"sprung_mass",
               "A moving oscillator: a body on a spring and damper above a contact point moving at the "
               "prescribed speed, its bounce (along j) an unknown coupled with the structure through the contact "
               "force (static weight included); starts in static equilibrium (on the rod: the only load, on the "
               "rod from t = 0)",
               {real("mass", "Body mass M_v (sprung)", "kg").positive().required(),
                real("stiffness", "Suspension stiffness k_v", "N/m").positive().required(),
                real("damping", "Suspension damping c_v", "N s/m").non_negative().def(0.0),
                real("wheel_mass", "Unsprung mass m_w riding on the structure (moving-mass inertia)", "kg")
                    .non_negative().def(0.0),
                contact},
               {moves("sprung mass")}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r.add(t);
  }
  {
    TypeInfo t{"vehicle",
               "A rigid body with bounce and pitch on several axles (beam), each with its own suspension; the "
               "motion keys give the leading axle's path (the vehicle comes from rigid ground before entry_time)",
               {real("mass", "Body mass M_v (sprung)", "kg").positive().required(),
                real("pitch_inertia", "Body pitch inertia J_v about its centre", "kg m^2").positive().required(),
                real_list("axle_offsets", "Axle positions e_a from the body's centre, positive ahead", "m").required(),
                real_list("stiffness", "Suspension stiffness k_a per axle (one value: every axle)", "N/m")
                    .positive().required(),
                real_list("damping", "Suspension damping c_a per axle (one value: every axle)", "N s/m")
                    .non_negative().def("[0]"),
                real_list("wheel_masses", "Unsprung mass m_w per axle (one value: every axle)", "kg")
                    .non_negative().def("[0]"),
                contact},
               {moves("vehicle"), per_axle("stiffness", "axle_offsets"), per_axle("damping", "axle_offsets"),
                per_axle("wheel_masses", "axle_offsets"),
                [](const ParameterList& s, const CheckContext& ctx) {
                  auto e = numbers(s, "axle_offsets");
                  if (e.size() < 2) ctx.fail("axle_offsets", "at least 2 axles (one: use type sprung_mass)",
                                             std::to_string(e.size()));
                  std::sort(e.begin(), e.end());
                  for (std::size_t i = 1; i < e.size(); ++i)
                    if (e[i] == e[i - 1]) ctx.fail("axle_offsets", "distinct offsets", "two at " + format_number(e[i]));
                }}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r.add(t);
  }
  {
    Param gen = section("generator", "A generic articulated train instead of the lists: a leading and a trailing "
                                     "car and `coaches` articulated coaches, all of length D, on N + 3 two-axle "
                                     "bogies D apart (one at each joint), axles d apart, P each");
    gen.only_if_given();
    gen.add(integer("coaches", "Number N of articulated coaches between the end cars").at_least(1).at_most(100).required());
    gen.add(real("coach_length", "Coach length D (the bogie spacing)", "m").positive().required());
    gen.add(real("bogie_axle_spacing", "Axle spacing d within a bogie (< D)", "m").positive().required());
    gen.add(real("axle_load", "Force P of every axle, acting along -j", "N").positive().required());
    gen.check([](const ParameterList& s, const CheckContext& ctx) {
      if (s.get<double>("bogie_axle_spacing") >= s.get<double>("coach_length"))
        ctx.fail("bogie_axle_spacing", "less than coach_length = " + format_number(s.get<double>("coach_length")),
                 format_number(s.get<double>("bogie_axle_spacing")));
    });
    TypeInfo t{"axle_train",
               "A train of moving forces (no inertia) at fixed distances behind its head, the first axle, whose path "
               "the motion keys give: lists of offsets and loads, or a generator",
               {real_list("offsets", "Axle distances e_a behind the head (the first 0), increasing", "m").non_negative(),
                real_list("loads", "Axle forces P_a along -j (one value: every axle)", "N").positive(),
                gen},
               {moves("axle train"), per_axle("loads", "offsets"),
                [](const ParameterList& s, const CheckContext& ctx) {
                  const bool lists = s.isParameter("offsets") || s.isParameter("loads");
                  if (lists == s.isSublist("generator"))
                    ctx.fail(lists ? "generator" : "offsets", "either offsets and loads, or generator",
                             lists ? "both" : "neither");
                  if (!lists) return;
                  if (!s.isParameter("offsets") || !s.isParameter("loads"))
                    ctx.fail(s.isParameter("offsets") ? "loads" : "offsets", "both offsets and loads", "one of them");
                  const auto e = numbers(s, "offsets");
                  if (e.empty() || e[0] != 0.0) ctx.fail("offsets", "a list starting at 0 (the head)", "another first value");
                  for (std::size_t i = 1; i < e.size(); ++i)
                    if (!(e[i] > e[i - 1])) ctx.fail("offsets", "increasing offsets", "offsets[" + std::to_string(i) + "] = " + format_number(e[i]));
                }}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r.add(t);
  }
}

std::shared_ptr<TypeRegistry> load_types() {
  auto r = std::make_shared<TypeRegistry>("load");
  {
    TypeInfo t{"moving_mass",
               "A point mass riding on the structure: its weight plus its inertia (with the centrifugal, "
               "Coriolis and acceleration terms)",
               {real("mass", "Mass M", "kg").positive(),
                real("mass_fraction", "Mass as a fraction p of structure + mass: M = p/(1-p) * structure mass", "")
                    .positive()
                    .below(1.0)},
               {exactly_one({"mass", "mass_fraction"}), moves("moving mass")}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r->add(t);
  }
  {
    TypeInfo t{"moving_force",
               "A point force without inertia (the classic moving-load idealisation)",
               {real("force", "Force magnitude, acting along -j", "N").positive(),
                vector3("force_vector", "Force as a fixed-frame vector (i, j, k) (rod; a beam takes only j)", "N"),
                real("mass", "Give the force as the weight M g of this mass", "kg").positive(),
                real("mass_fraction", "Force as the weight of a mass given as a fraction of structure + mass", "")
                    .positive()
                    .below(1.0)},
               {exactly_one({"force", "force_vector", "mass", "mass_fraction"}), moves("moving force")}};
    for (const auto& p : motion_params()) t.params.push_back(p);
    r->add(t);
  }
  r->add({"coupled_mass",
          "A point mass that moves by itself along the deforming structure (two-way coupling): its position "
          "is an unknown, driven by gravity along the local tangent, the structure's motion, an optional drive "
          "and resistance, Coulomb friction; the run ends at the first event (the mass leaves the structure, lifts "
          "off, or stops and sticks)",
          {real("mass", "Mass M", "kg").positive().required(),
           real("start", "Initial position sigma0 along the structure (default 0)", "m").non_negative(),
           real("speed", "Initial velocity along +s (negative: towards s = 0)", "m/s").def(0.0),
           real("drive", "Constant drive force along the tangent d3 (a robot's traction; negative: towards s = 0)", "N")
               .def(0.0),
           real("resistance", "Viscous resistance c: a force -c sigma' d3 on the mass", "N s/m")
               .non_negative()
               .def(0.0),
           choice("resistance_through",
                  "air: the resistance acts on the mass alone (docs/rod.md, Coupled mass; its power c sigma' d3 . p' can "
                  "turn negative where the structure moves along its tangent faster than the mass moves along it); "
                  "structure: a force pair between mass and structure (wheels, a motor), the structure taking "
                  "+c sigma' d3, its loss c sigma'^2 never negative (a beam's load is transverse: both act alike "
                  "there)",
                  enum_names<ResistanceThrough>())
               .def("air"),
           real("friction", "Coulomb friction coefficient mu between the mass and the structure: a tangential contact "
                            "force -mu |C_perp| sign(sigma'); where the mass stops and the friction can hold it, it "
                            "sticks (the event stick)", "").non_negative().def(0.0),
           choice("contact", "bilateral: threaded on the structure (a bead); unilateral: resting on its upper (+d2, +w) "
                             "side, it lifts off where the normal contact force would pull",
                  enum_names<Contact>())
               .def("bilateral")},
          {}});
  add_vehicle_types(*r);
  return r;
}

// The schema of one end condition parameter and the checks of a type, from its declaration.
Param end_parameter(const EndParameter& p) {
  if (p.vector) return vector3(p.key, p.doc, p.units).def(p.vector_default);
  return real(p.key, p.doc, p.units).def(p.number_default);
}

Check nonzero(const std::string& key) {
  return [key](const ParameterList& s, const CheckContext& ctx) {
    const auto a = numbers(s, key);
    if (std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) == 0.0) ctx.fail(key, "a non-zero axis", "[0, 0, 0]");
  };
}

Check perpendicular(const EndPerpendicular& q) {
  return [key = std::string(q.key), other = std::string(q.other), expected = std::string(q.expected)](
             const ParameterList& s, const CheckContext& ctx) {
    const auto a = numbers(s, other), e = numbers(s, key);
    const double dot = a[0] * e[0] + a[1] * e[1] + a[2] * e[2];
    const double na = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    const double ne = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    if (std::abs(dot) > 1e-12 * na * ne) ctx.fail(key, expected, "a dot product of " + format_number(dot / (na * ne)));
  };
}

// The end condition types of traverse/core/end_types.hpp.
std::shared_ptr<TypeRegistry> end_types() {
  auto r = std::make_shared<TypeRegistry>("end condition");
  for (const auto& d : end_type_declarations()) {
    TypeInfo t{d.word, d.doc, {}, {}};
    for (const auto& p : d.parameters) {
      t.params.push_back(end_parameter(p));
      if (p.direction) t.checks.push_back(nonzero(p.key));
    }
    for (const auto& q : d.perpendicular) t.checks.push_back(perpendicular(q));
    r->add(t);
  }
  return r;
}

std::shared_ptr<TypeRegistry> probe_types() {
  auto r = std::make_shared<TypeRegistry>("probe");
  r->add({"deflection", "Beam: transverse deflection w (positive up) at a fixed point [m]",
          {real("at", "Position along the beam", "m").non_negative().required()}, {}});
  r->add({"acceleration", "Beam: transverse acceleration w_tt (positive up) at a fixed point, from the modal "
                          "accelerations of the equation of motion [m/s^2]",
          {real("at", "Position along the beam", "m").non_negative().required()}, {}});
  r->add({"point",
          "Rod: a vector quantity at a fixed arclength (linear interpolation between nodes), 3 components",
          {real("at", "Arclength", "m").non_negative().required(),
           choice("quantity", "position r [m], velocity u [m/s], spin omega [rad/s], curvature kappa [1/m], "
                              "force n [N], moment m [N m], a director d1, d2, d3, or the strain v = dr/ds in body components "
                              "(shears v1, v2, stretch v3; e3 for the inextensible rod) [1]",
                  enum_names<Quantity>()).required(),
           choice("frame", "Components in the fixed frame (i, j, k) or the body frame (d1, d2, d3)",
                  enum_names<Frame>()).def("fixed")},
          {[](const ParameterList& s, const CheckContext& ctx) {
            const auto q = s.get<std::string>("quantity");
            if ((q == "position" || q[0] == 'd') && s.get<std::string>("frame") == "body")
              ctx.fail("frame", "fixed for quantity " + q + " (it is defined in the fixed frame)", "body");
          }}});
  return r;
}

std::shared_ptr<TypeRegistry> continuation_probe_types() {
  auto cprobes = std::make_shared<TypeRegistry>("continuation probe");
  cprobes->add({"point", "One component of a quantity at a fixed arclength (linear interpolation)",
                {real("at", "Arclength", "m").non_negative().required(),
                 choice("quantity", "position r [m], curvature kappa [1/m], force n [N], moment m [N m], director d1, d2, d3",
                        {"position", "kappa", "n", "m", "d1", "d2", "d3"}).required(),
                 choice("component", "Component: x, y, z (fixed frame) or 1, 2, 3 (body frame)",
                        {"x", "y", "z", "1", "2", "3"}).required()},
                {[](const ParameterList& s, const CheckContext& ctx) {
                   const auto c = s.get<std::string>("component");
                   const auto q = s.get<std::string>("quantity");
                   const bool body = c == "1" || c == "2" || c == "3";
                   if (body && (q == "position" || q[0] == 'd'))
                     ctx.fail("component", "x, y or z for quantity " + q + " (defined in the fixed frame)", c);
                 }}});
  cprobes->add({"end_compression", "Compressive force at the right end along k, -n(L) . k [N]", {}, {}});
  return cprobes;
}

// time.adaptive (docs/adaptive.md).
Param adaptive_section() {
  Param a = section("adaptive", "Step sizes chosen by a local error estimate instead of a fixed dt (docs/adaptive.md): "
                                "time.dt is the first step; the output times stay those of the fixed-dt run "
                                "(every output.every steps of time.dt), where the steps land");
  a.only_if_given();
  a.add(real("tolerance", "Relative error asked of the run (rod: in the quantities 'on'; beam: in the modal "
                          "state), relative to the largest value of the quantity in the run so far (position, "
                          "orientation: the displacement and rotation since the start); each step's local error "
                          "is held at tolerance * (tolerance / 1e-3)^(1/p) for a scheme of order p, so the error "
                          "falls in proportion to the tolerance", "").positive().at_most(0.1).required());
  a.add(word_list("on", "Rod: the quantities whose local error is controlled: position and orientation of the "
                        "nodes (displacement-type: a fast mode counts by how far it moves the rod), u, omega, kappa "
                        "(the state; the grid's bending waves then force short steps)",
                  {"position", "orientation", "u", "omega", "kappa"}).def("[position, orientation]"));
  a.add(real("absolute_position", "Rod: absolute tolerance on the position", "m").non_negative().def(0.0));
  a.add(real("absolute_orientation", "Rod: absolute tolerance on the orientation", "rad").non_negative().def(0.0));
  a.add(real("absolute_u", "Rod: absolute tolerance on the velocity u", "m/s").non_negative().def(0.0));
  a.add(real("absolute_omega", "Rod: absolute tolerance on the spin omega", "rad/s").non_negative().def(0.0));
  a.add(real("absolute_kappa", "Rod: absolute tolerance on the curvature kappa", "1/m").non_negative().def(0.0));
  a.add(real("dt_min", "Smallest step: a step that would have to be shorter ends the run (exit 3); "
                       "default 1e-6 time.dt", "s").positive());
  a.add(real("dt_max", "Largest step (default: no bound but the output interval)", "s").positive());
  a.add(real("growth", "Largest factor from one step to the next", "").above(1.0).at_most(10.0).def(2.0));
  a.add(real("shrink", "Smallest factor from a rejected step to its retry", "").positive().below(1.0).def(0.2));
  a.add(real("safety", "Factor on the step the error estimate calls optimal", "").positive().at_most(1.0).def(0.9));
  a.add(integer("newton_target", "Rod: after a step that needed more Newton iterations than this, the next step "
                                 "does not grow").at_least(1).def(6.0));
  a.add(boolean("land_on_nodes", "Rod: the steps also end where a moving load (not a coupled mass) enters the rod "
                                 "or reaches a node, where its force on the nodes has a kink in time").def("true"));
  a.check([](const ParameterList& s, const CheckContext& ctx) {
    if (s.isParameter("dt_min") && s.isParameter("dt_max") && s.get<double>("dt_min") > s.get<double>("dt_max"))
      ctx.fail("dt_min", "at most dt_max = " + format_number(s.get<double>("dt_max")) + " s",
               format_number(s.get<double>("dt_min")) + " s");
  });
  return a;
}

// beam.damping (docs/beam.md "Structural damping").
Param damping_section() {
  Param damping = section("damping", "Structural damping in the beam's modes (default none): ratio (every mode), "
                                     "ratios (one per mode), or Rayleigh mass and/or stiffness coefficients");
  damping.only_if_given();
  damping.add(real("ratio", "Damping ratio zeta of every mode", "").non_negative().below(1.0));
  damping.add(real_list("ratios", "Damping ratio zeta_i of each mode (as many as beam.modes)", "").non_negative().below(1.0));
  damping.add(real("mass", "Rayleigh coefficient a of C = a M + b K (zeta_i = a / (2 omega_i) + b omega_i / 2)", "1/s")
                  .non_negative());
  damping.add(real("stiffness", "Rayleigh coefficient b of C = a M + b K", "s").non_negative());
  damping.check([](const ParameterList& s, const CheckContext& ctx) {
    const int given = int(s.isParameter("ratio")) + int(s.isParameter("ratios")) +
                      int(s.isParameter("mass") || s.isParameter("stiffness"));
    if (given != 1)
      ctx.fail(s.isParameter("ratios") ? "ratios" : "", "exactly one of 'ratio', 'ratios' and the Rayleigh "
               "coefficients 'mass' / 'stiffness'", given == 0 ? "none" : std::to_string(given) + " of them");
  });
  return damping;
}

// rod.model and what it reads: the stiffnesses of the strains, the shear coefficient, the
// Kelvin-Voigt viscosities (docs/rod.md, "Extensible and shearable rods", "Material damping").
void add_rod_strain_keys(Param& rod) {
  rod.add(choice("model", "inextensible: the centreline does not stretch or shear (dr/ds = d3); extensible: it "
                          "stretches, v = e3 (1 + n3 / (E A)); shearable: it stretches and shears, v - e3 = C n with "
                          "C = diag(1/(k G A), 1/(k G A), 1/(E A)) (special Cosserat rod)",
                 enum_names<RodStrain>()).def("inextensible"));
  rod.add(real("shear_coefficient", "Shear coefficient k of shearable (default: Cowper's of the section: solid circle "
                                    "6 (1 + nu) / (7 + 6 nu), tube 6 (1 + nu) (1 + m^2)^2 / ((7 + 6 nu) (1 + m^2)^2 + "
                                    "(20 + 12 nu) m^2) with m = inner / outer radius, rectangle 10 (1 + nu) / (12 + "
                                    "11 nu); required for a section given by its properties)", "").positive().at_most(1.0));
  rod.add(real("axial_stiffness", "Axial stiffness E A of extensible and shearable (default: E times the area)", "N")
              .positive());
  rod.add(real("shear_stiffness", "Shear stiffness k G A of shearable (default: k G times the area)", "N").positive());
  Param damping = section("damping", "Kelvin-Voigt material damping: n gains B_se v_t, m gains B_bt kappa_t. For a "
                                     "damping ratio zeta at circular frequency w of a mode that strains one kind of "
                                     "deformation, give B = 2 zeta S / w with S its stiffness (E A, k G A, E I, G J)");
  damping.only_if_given();
  damping.add(real("axial", "Viscosity of the stretch v3 (extensible, shearable)", "N s").non_negative().def(0.0));
  damping.add(real("shear", "Viscosity of the shears v1, v2 (shearable)", "N s").non_negative().def(0.0));
  damping.add(real("bending", "Viscosity of the bending curvatures kappa1, kappa2", "N m^2 s").non_negative().def(0.0));
  damping.add(real("torsion", "Viscosity of the twist kappa3", "N m^2 s").non_negative().def(0.0));
  rod.add(damping);
  rod.check([](const ParameterList& s, const CheckContext& ctx) {
    const RodStrain m = enum_of<RodStrain>(s.get<std::string>("model"));
    const std::string word = name_of(m);
    if (m == RodStrain::inextensible && s.isParameter("axial_stiffness"))
      ctx.fail("axial_stiffness", "no axial stiffness for the inextensible rod (rod.model extensible or shearable)",
               "rod.model " + word);
    for (const char* k : {"shear_coefficient", "shear_stiffness"})
      if (m != RodStrain::shearable && s.isParameter(k))
        ctx.fail(k, std::string("no ") + k + " for a rod that does not shear (rod.model shearable)", "rod.model " + word);
    const bool properties = s.sublist("section").get<std::string>("type") == "properties";
    if (m == RodStrain::shearable && properties && !s.isParameter("shear_coefficient") &&
        !s.isParameter("shear_stiffness"))
      ctx.fail("shear_coefficient", "a shear coefficient (or shear_stiffness) for a shearable rod whose section is "
               "given by its properties", "none");
    if (!s.isSublist("damping")) return;
    const auto& d = s.sublist("damping");
    if (m == RodStrain::inextensible && d.get<double>("axial") > 0.0)
      ctx.fail("damping.axial", "no axial viscosity for the inextensible rod (rod.model extensible or shearable)",
               "rod.model " + word);
    if (m != RodStrain::shearable && d.get<double>("shear") > 0.0)
      ctx.fail("damping.shear", "no shear viscosity for a rod that does not shear (rod.model shearable)",
               "rod.model " + word);
  });
}

// Cowper's shear coefficient of a section for Poisson ratio nu; 0 for a section given by its
// properties (its k must be given).
double cowper_shear_coefficient(const SectionSpec& sec, double nu) {
  if (sec.shape == "solid_circle") return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
  if (sec.shape == "hollow_circle") {
    const double q = std::pow(1.0 + sec.radius_ratio * sec.radius_ratio, 2);
    return 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * sec.radius_ratio * sec.radius_ratio);
  }
  if (sec.shape == "rectangle") return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
  return 0.0;
}

const std::vector<std::string> kBeamFields = {"deflection", "slope", "bending_moment"};
const std::vector<std::string> kRodFields = {"u", "omega", "kappa", "n", "m", "r", "R", "v", "stretch", "axial_force"};

Param build_schema() {
  Param root = section("", "traverse scene");
  root.add(choice("model", "Which structural model to run", {kBeam, kRod}).required());
  root.add(text("title", "Free text describing the scene").def("''"));
  root.add(real("gravity", "Gravitational acceleration g, acting along -j", "m/s^2").non_negative().def(constants::standard_gravity));

  Param beam = section(kBeam, "Small-deflection Euler–Bernoulli beam (model: beam)");
  beam.when("model", kBeam);
  beam.add(real("length", "Beam length L", "m").positive().required());
  beam.add(real("youngs_modulus", "Young's modulus E", "Pa").positive().required());
  beam.add(real("density", "Material density rho", "kg/m^3").positive().required());
  beam.add(typed("section", "Cross-section", section_types()).required());
  beam.add(choice("supports", "End conditions at x = 0 and x = L", enum_names<Supports>()).required());
  beam.add(integer("modes", "Number of Galerkin modes (the beam's own eigenmodes)").at_least(1).at_most(200).def(3.0));
  beam.add(integer("quadrature_points", "Gauss points per mesh cell for the Galerkin integrals").at_least(1).at_most(20).def(6.0));
  beam.add(choice("integrator", "rk4: classical 4th-order Runge–Kutta (reference); newmark: average-acceleration "
                                "Newmark, unconditionally stable, 2nd order", enum_names<BeamIntegrator>()).def("rk4"));
  beam.add(boolean("self_weight", "Include the beam's own weight; false: the deflections are taken about the "
                                  "beam's static equilibrium under its weight (the deck's sag cambered out, the "
                                  "usual convention of bridge dynamics: a vehicle then enters on a level deck)")
               .def("true"));
  beam.add(damping_section());
  beam.check([](const ParameterList& s, const CheckContext& ctx) {
    if (!s.isSublist("damping") || !s.sublist("damping").isParameter("ratios")) return;
    const std::size_t k = numbers(s.sublist("damping"), "ratios").size();
    if (static_cast<int>(k) != s.get<int>("modes"))
      ctx.fail("damping.ratios", "one ratio per mode (beam.modes = " + std::to_string(s.get<int>("modes")) + ")",
               std::to_string(k) + " ratios");
  });
  root.add(beam);

  Param rod = section(kRod, "Cosserat rod, initially straight along k (model: rod): inextensible and unshearable, "
                            "extensible or shearable (rod.model)");
  rod.when("model", kRod);
  rod.add(real("length", "Rod length L", "m").positive().required());
  rod.add(real("youngs_modulus", "Young's modulus E", "Pa").positive().required());
  rod.add(real("poisson_ratio", "Poisson ratio nu (G = E / (2 (1 + nu)))", "").above(-1.0).below(0.5));
  rod.add(real("shear_modulus", "Shear modulus G (instead of the Poisson ratio)", "Pa").positive());
  rod.add(real("density", "Material density rho", "kg/m^3").positive().required());
  rod.add(typed("section", "Cross-section", section_types()).required());
  rod.add(vector3("intrinsic_curvature", "Intrinsic curvature kappa0 in body components", "1/m").def("[0, 0, 0]"));
  rod.check(exactly_one({"poisson_ratio", "shear_modulus"}));
  add_rod_strain_keys(rod);
  root.add(rod);

  Param ends = section("ends", "End conditions of the rod, 6 scalar conditions each");
  ends.when("model", kRod);
  ends.add(typed("left", "End at s = 0 (at the origin)", end_types()).required());
  ends.add(typed("right", "End at s = L", end_types()).required());
  root.add(ends);

  Param mesh = section("mesh", "Nodes along the structure (uniform spacing): give nodes or ds");
  mesh.add(integer("nodes", "Number of nodes N + 1 (default 101)").at_least(2));
  mesh.add(real("ds", "Node spacing (the length must be a whole number of spacings)", "m").positive());
  mesh.check([](const ParameterList& s, const CheckContext& ctx) {
    if (s.isParameter("nodes") && s.isParameter("ds")) ctx.fail("ds", "either 'nodes' or 'ds', not both", "both");
  });
  root.add(mesh);

  Param scheme = section("scheme", "Generalised-alpha discretisation of the rod in s and t");
  scheme.when("model", kRod);
  scheme.add(real("rho_inf", "Spectral radius at infinite frequency in time: 1 = no numerical damping "
                             "(centred, energy conserving); < 1 damps the highest frequencies", "").at_least(0.0).at_most(1.0).def(1.0));
  scheme.add(real("rho_inf_space", "The same in space: 1 = plain box scheme in s (12 unknowns per node); < 1 "
                                   "carries the spatial derivative history (24 unknowns per node)", "").at_least(0.0).at_most(1.0).def(1.0));
  Param alpha = section("parameters", "The six parameters directly (instead of rho_inf, rho_inf_space)");
  alpha.only_if_given();
  for (const char* k : {"as", "bs", "gs", "at", "bt", "gt"})
    alpha.add(real(k, std::string("Parameter ") + k, "").above(0.0).at_most(1.0).required());
  scheme.add(alpha);
  scheme.add(choice("planar", "Planar fast path (docs/solver.md): auto = solve the in-plane system (6 unknowns per "
                              "node instead of 12, same answers) when the rod, its initial state, the loads, gravity "
                              "and the end conditions are symmetric about one plane; on = require it (a scene that is "
                              "not planar is refused); off = always the 3D system",
                    enum_names<PlanarMode>()).def("auto"));
  scheme.check([](const ParameterList& s, const CheckContext& ctx) {
    if (s.isSublist("parameters") && (s.get<double>("rho_inf") != 1.0 || s.get<double>("rho_inf_space") != 1.0))
      ctx.fail("parameters", "either 'parameters' or rho_inf / rho_inf_space, not both", "both");
  });
  root.add(scheme);

  Param init = section("initial_state", "Where the rod starts");
  init.when("model", kRod);
  init.add(choice("type", "static: equilibrium under the dead loads (gravity and the loads on the rod at t = 0), "
                          "computed by Newton with load stepping on the static form of the same discretisation; "
                          "rest: straight and unloaded; file: a state saved by a continuation run; arch: form an "
                          "arch (buckle the straight rod upwards by a compressive end load until the ends are "
                          "end_to_end apart, pin them there, raise gravity from 0 to g)",
                  enum_names<InitialStateType>()).def("static"));
  init.add(text("file", "type file: the continuation output file (HDF5) holding the state"));
  init.add(text("state", "type file: name of the state in the file (/states/<name>)").def("final"));
  init.add(real("end_to_end", "type arch: distance between the pinned ends along k", "m").positive());
  init.add(boolean("loaded", "type arch: start in equilibrium with the prescribed load on the arch at t = 0 (one "
                             "moving force or mass; one Newton solve after the formation). false: the formed arch "
                             "without it; a load starting inside the arch then appears as a step, which excites "
                             "grid-scale waves that the undamped scheme keeps (a load entering at a pin weighs on the "
                             "support alone: the same start either way)")
               .def("false"));
  init.check([](const ParameterList& s, const CheckContext& ctx) {
    const auto type = s.get<std::string>("type");
    if (type == "file" && !s.isParameter("file")) ctx.fail("file", "the continuation output file (type: file)", "nothing");
    if (type != "file" && s.isParameter("file")) ctx.fail("file", "no file unless type: file", "a file");
    if (type == "arch" && !s.isParameter("end_to_end"))
      ctx.fail("end_to_end", "the end-to-end distance of the arch (type: arch)", "nothing");
    if (type != "arch" && s.isParameter("end_to_end")) ctx.fail("end_to_end", "no end_to_end unless type: arch", "a value");
    if (type != "arch" && s.get<bool>("loaded"))
      ctx.fail("loaded", "loaded: true only with type: arch (a static start always includes the loads at t = 0)",
               "true");
  });
  root.add(init);

  Param cont = section("continuation", "Continuation of static states: with this section, traverse run follows a "
                                       "branch of equilibria in one parameter instead of running the dynamics");
  cont.when("model", kRod);
  cont.only_if_given();
  cont.add(choice("parameter", "The continued parameter: end_load (compressive force on the right end along k, N), "
                               "end_position (the right end's position along k, m), gravity_factor (times g), "
                               "load_position (sigma of the scene's single load, m), load_magnitude (its force, N)",
                  enum_names<ContinuationParameter>()).required());
  cont.add(real("start", "Start value of the parameter (default: its value in the scene: the load's start and "
                         "force, gravity factor 1 with gravity > 0, end load 0, the right end's position)", ""));
  cont.add(real("stop", "The run ends where the parameter reaches this value", "").required());
  cont.add(real("step", "Initial step of the parameter (its size; the direction is towards stop)", "").positive().required());
  cont.add(real("min_step", "Smallest step before the run gives up", "").positive().def(1e-8));
  cont.add(real("max_step", "Largest step (default: 10 times step)", "").positive());
  cont.add(choice("method", "arclength: pseudo-arclength continuation (passes folds); natural: parameter stepping",
                  enum_names<ContinuationMethod>()).def("arclength"));
  cont.add(integer("max_steps", "Largest number of continuation steps per branch").at_least(1).def(1000.0));
  cont.add(boolean("stability", "Compute the small-vibration eigenvalues of every state (unstable-mode count, "
                                "fold and pitchfork detection)").def("true"));
  cont.add(integer("eigenvalues", "Eigenvalues computed nearest zero per state").at_least(1).at_most(50).def(6.0));
  cont.add(boolean("switch_branches", "Follow the symmetry-broken branch from each pitchfork found").def("true"));
  cont.add(real("branch_amplitude", "Size of the step off the primary branch along the null vector at a pitchfork "
                                    "(a few percent of the length keeps the first continuation step on the new branch)",
                "m").positive().def(0.02));
  cont.add(collection("probes", "Scalars recorded at every continuation point, each under a name of your choice",
                      continuation_probe_types()));
  cont.check([](const ParameterList& s, const CheckContext& ctx) {
    if (s.isParameter("start") && s.get<double>("start") == s.get<double>("stop"))
      ctx.fail("stop", "a value different from start", format_number(s.get<double>("stop")));
  });
  root.add(cont);

  root.add(collection("loads", "Moving loads, each under a name of your choice", load_types()));

  Param time = section("time", "Time stepping");
  time.add(real("dt", "Time step; auto: beam: a twentieth of the period of the highest mode, at most the time a "
                      "load needs to cross one mesh cell; rod: ds / v of the fastest load, v its largest speed "
                      "while on the rod (a load at constant speed sits on a node at every step; an accelerating "
                      "one crosses at most one cell per step)", "s").positive().allow_auto().def("auto"));
  time.add(real("end", "End time; auto: when the last load leaves the structure (a coupled_mass: at its first event, "
                       "at the latest at time.auto_limit)", "s").positive().allow_auto().def("auto"));
  time.add(real("auto_limit", "With a coupled_mass and time.end: auto: the latest end time; reached without an event, "
                              "the run ends there with the event time_limit (unused otherwise)", "s").positive().def(10.0));
  time.add(adaptive_section());
  root.add(time);

  root.add(pass_through("solver", "Rod solver parameters (Newton, linear solver, NOX and Stratimikos sublists), "
                                  "handed to the solver: see docs/solver.md").when("model", kRod));

  Param out = section("output", "What is written, and where");
  out.add(text("file", "HDF5 output file; auto: the scene file's name with .h5, in the working directory "
                       "(the command line's -o wins)").def("auto"));
  out.add(integer("every", "Write every this many time steps (the first and last states are always written); auto: "
                          "beam: 4 outputs per period of the fastest motion kept (the highest mode, or a faster "
                          "suspension), rod: every time step (with time.dt auto, one per mesh cell the fastest load "
                          "crosses)")
              .at_least(1)
              .allow_auto()
              .def("auto"));
  out.add(real("restart_interval", "Rod runs: wall time between restart points (docs/reliability.md); one is also "
                                   "stored at the start, at the end, on a signal and on a failure; 0: after every "
                                   "output step (the command line's --restart-interval wins)", "s")
              .non_negative()
              .def(60.0));
  out.add(real("flush_interval", "Wall time between flushes of the output file while the run goes on (the steps "
                                 "flushed are readable by another process and survive a kill); 0: after every "
                                 "output step", "s")
              .non_negative()
              .def(1.0));
  out.add(real("progress_interval", "Wall time between progress reports on stderr (--progress, or a terminal); 0: "
                                    "at every time step", "s")
              .non_negative()
              .def(1.0));
  out.add(collection("probes", "Time series of chosen quantities, each under a name of your choice", probe_types()));
  out.add(word_list("fields", "Fields written at every node at each output step (beam: deflection, slope, "
                              "bending_moment; rod: u, omega, kappa, n, m, v (body components), r (centreline), "
                              "R (rows d1, d2, d3), stretch |v| and axial_force n . v / |v| (one value per node))").def("[]"));
  root.add(out);

  root.check([](const ParameterList& s, const CheckContext& ctx) {
    const std::string model = s.get<std::string>("model");
    const double length = s.sublist(model).get<double>("length");
    const auto& probes = s.sublist("output").sublist("probes");
    for (const auto& entry : probes) {
      const auto& pr = probes.sublist(entry.first);
      const std::string key = "output.probes." + entry.first;
      const std::string type = pr.get<std::string>("type");
      if ((type != "point") != (model == kBeam))
        ctx.fail(key + ".type", std::string("a probe type of model ") + model + " (" +
                 (model == kBeam ? "deflection, acceleration" : "point") + ")", "'" + type + "'");
      if (pr.get<double>("at") > length)
        ctx.fail(key + ".at", "a position on the structure, in [0, " + format_number(length) + "]",
                 format_number(pr.get<double>("at")));
    }
    const auto fields = words(s.sublist("output"), "fields");
    const auto& allowed = model == kBeam ? kBeamFields : kRodFields;
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (std::find(allowed.begin(), allowed.end(), fields[i]) == allowed.end())
      {
        std::string list;
        for (const auto& f : allowed) list += (list.empty() ? "" : ", ") + f;
        ctx.fail("output.fields[" + std::to_string(i) + "]",
                 std::string("a field of model ") + model + ", one of {" + list + "}", "'" + fields[i] + "'");
      }
    const auto& loads = s.sublist("loads");
    for (const auto& entry : loads) {
      const auto& l = loads.sublist(entry.first);
      const std::string key = "loads." + entry.first;
      if (l.isParameter("start") && l.get<double>("start") > length)
        ctx.fail(key + ".start", "a position on the structure, in [0, " + format_number(length) + "]",
                 format_number(l.get<double>("start")));
      if (model == kBeam && l.isParameter("force_vector")) {
        const auto f = numbers(l, "force_vector");
        if (f[0] != 0.0 || f[2] != 0.0)
          ctx.fail(key + ".force_vector", "a vertical force [0, Fy, 0] for a beam (it bends in the (j, k) plane)",
                   "[" + format_number(f[0]) + ", " + format_number(f[1]) + ", " + format_number(f[2]) + "]");
      }
    }
    const auto& mesh = s.sublist("mesh");
    if (mesh.isParameter("ds")) {
      const double ds = mesh.get<double>("ds");
      const double cells = length / ds;
      if (std::abs(cells - std::round(cells)) > 1e-9 * std::max(1.0, cells) || std::round(cells) < 1.0)
        ctx.fail("mesh.ds", "a spacing that divides the length " + format_number(length) + " into whole cells",
                 format_number(ds) + " (" + format_number(cells) + " cells)");
      else if (model != kBeam && std::round(cells) < 2.0)
        ctx.fail("mesh.ds", "at least 2 cells along a rod (ds <= " + format_number(length / 2.0) + ")",
                 format_number(ds) + " (1 cell)");
      else if (std::round(cells) > 2147483646.0)  // mesh.nodes is an int
        ctx.fail("mesh.ds", "at most 2147483646 cells (ds >= " + format_number(length / 2147483646.0) +
                 "; the node count is a 32-bit integer)", format_number(ds) + " (" + format_number(cells) + " cells)");
    } else if (model != kBeam && mesh.isParameter("nodes") && mesh.get<int>("nodes") < 3) {
      ctx.fail("mesh.nodes", "at least 3 nodes (2 cells) along a rod", std::to_string(mesh.get<int>("nodes")));
    }
  });
  return root;
}

Vec3 vec3_of(const ParameterList& p, const std::string& key) {
  const auto a = numbers(p, key);
  return Vec3(a[0], a[1], a[2]);
}

SectionSpec build_section(const ParameterList& s) {
  SectionSpec out;
  out.shape = s.get<std::string>("type");
  const double pi = constants::pi;
  if (out.shape == "solid_circle") {
    const double r = s.get<double>("radius");
    out.area = pi * r * r;
    out.I1 = out.I2 = pi * std::pow(r, 4) / 4.0;
    out.J = 2.0 * out.I1;
  } else if (out.shape == "hollow_circle") {
    const double ro = s.get<double>("outer_radius"), ri = s.get<double>("inner_radius");
    out.area = pi * (ro * ro - ri * ri);
    out.I1 = out.I2 = pi * (std::pow(ro, 4) - std::pow(ri, 4)) / 4.0;
    out.J = 2.0 * out.I1;
    out.radius_ratio = ri / ro;
  } else if (out.shape == "rectangle") {
    const double b = s.get<double>("width"), h = s.get<double>("height");
    out.area = b * h;
    out.I1 = b * h * h * h / 12.0;
    out.I2 = h * b * b * b / 12.0;
    // Saint-Venant torsion constant of a rectangle, series truncated where converged.
    const double a = std::max(b, h), c = std::min(b, h);
    double sum = 0.0;
    for (int n = 1; n < 200; n += 2) sum += std::tanh(n * pi * a / (2.0 * c)) / std::pow(n, 5);
    out.J = a * c * c * c / 3.0 * (1.0 - 192.0 / std::pow(pi, 5) * c / a * sum);
  } else if (out.shape == "properties") {
    out.area = s.get<double>("area");
    out.I1 = s.get<double>("second_moment");
    out.I2 = s.isParameter("second_moment_2") ? s.get<double>("second_moment_2") : out.I1;
    out.J = s.isParameter("torsion_constant") ? s.get<double>("torsion_constant") : out.I1 + out.I2;
  } else {
    throw std::logic_error("build_section: unknown section type " + out.shape);
  }
  return out;
}

// The kinematics every moving load shares: speed, acceleration, entry end, start and entry time.
void read_kinematics(const ParameterList& l, double length, MovingLoadSpec& m) {
  m.speed = l.get<double>("speed");
  m.acceleration = l.get<double>("acceleration");
  m.entry = enum_of<Entry>(l.get<std::string>("entry"));
  m.start = l.isParameter("start") ? l.get<double>("start") : (m.entry == Entry::left ? 0.0 : length);
  m.entry_time = l.get<double>("entry_time");
}

MovingLoadSpec build_coupled_mass(const std::string& name, const ParameterList& l, double g) {
  MovingLoadSpec m;
  m.name = name;
  m.type = LoadType::coupled_mass;
  m.coupled = true;
  m.inertia = true;
  m.mass = l.get<double>("mass");
  m.force = Vec3(0.0, -m.mass * g, 0.0);
  const double v0 = l.get<double>("speed");
  m.entry = v0 < 0.0 ? Entry::right : Entry::left;
  m.speed = std::abs(v0);
  m.acceleration = 0.0;
  m.start = l.isParameter("start") ? l.get<double>("start") : 0.0;
  m.entry_time = 0.0;
  m.drive = l.get<double>("drive");
  m.resistance = l.get<double>("resistance");
  m.resistance_through = enum_of<ResistanceThrough>(l.get<std::string>("resistance_through"));
  m.friction = l.get<double>("friction");
  m.contact = enum_of<Contact>(l.get<std::string>("contact"));
  return m;
}

// A list of one value (every axle) or one per axle, as n values.
std::vector<double> per_axle_values(const ParameterList& l, const std::string& key, std::size_t n) {
  std::vector<double> v = numbers(l, key);
  if (v.size() == 1) v.assign(n, v[0]);
  return v;
}

// sprung_mass, vehicle, axle_train: their own keys (the motion keys are read by build_load).
void read_vehicle(const ParameterList& l, MovingLoadSpec& m, double g) {
  if (m.type == LoadType::sprung_mass) {
    m.mass = l.get<double>("mass");
    m.axle_offsets = {0.0};
    m.axle_stiffness = {l.get<double>("stiffness")};
    m.axle_damping = {l.get<double>("damping")};
    m.wheel_masses = {l.get<double>("wheel_mass")};
  } else if (m.type == LoadType::vehicle) {
    m.mass = l.get<double>("mass");
    m.pitch_inertia = l.get<double>("pitch_inertia");
    m.axle_offsets = numbers(l, "axle_offsets");
    const std::size_t n = m.axle_offsets.size();
    m.axle_stiffness = per_axle_values(l, "stiffness", n);
    m.axle_damping = per_axle_values(l, "damping", n);
    m.wheel_masses = per_axle_values(l, "wheel_masses", n);
  } else if (l.isSublist("generator")) {
    const auto& gen = l.sublist("generator");
    const int coaches = gen.get<int>("coaches");
    const double D = gen.get<double>("coach_length"), d = gen.get<double>("bogie_axle_spacing");
    for (int b = 0; b < coaches + 3; ++b)
      for (const double e : {b * D, b * D + d}) m.train_offsets.push_back(e);
    m.train_loads.assign(m.train_offsets.size(), gen.get<double>("axle_load"));
  } else {
    m.train_offsets = numbers(l, "offsets");
    m.train_loads = per_axle_values(l, "loads", m.train_offsets.size());
  }
  if (m.suspended()) {
    m.contact = enum_of<Contact>(l.get<std::string>("contact"));
    double weight = m.mass;
    for (const double mw : m.wheel_masses) weight += mw;
    m.force = Vec3(0.0, -weight * g, 0.0);
  } else {
    double total = 0.0;
    for (const double P : m.train_loads) total += P;
    m.force = Vec3(0.0, -total, 0.0);
  }
}

MovingLoadSpec build_load(const std::string& name, const ParameterList& l, double structure_mass, double length,
                          double g) {
  MovingLoadSpec m;
  m.name = name;
  m.type = enum_of<LoadType>(l.get<std::string>("type"));
  if (m.type == LoadType::coupled_mass) return build_coupled_mass(name, l, g);
  if (m.type == LoadType::sprung_mass || m.type == LoadType::vehicle || m.type == LoadType::axle_train) {
    read_vehicle(l, m, g);
    read_kinematics(l, length, m);
    return m;
  }
  m.inertia = m.type == LoadType::moving_mass;
  if (l.isParameter("mass")) m.mass = l.get<double>("mass");
  if (l.isParameter("mass_fraction")) {
    const double p = l.get<double>("mass_fraction");
    m.mass = p / (1.0 - p) * structure_mass;
  }
  if (l.isParameter("force")) m.force = Vec3(0.0, -l.get<double>("force"), 0.0);
  else if (l.isParameter("force_vector")) m.force = vec3_of(l, "force_vector");
  else m.force = Vec3(0.0, -m.mass * g, 0.0);
  if (!m.inertia && !l.isParameter("mass") && !l.isParameter("mass_fraction")) m.mass = 0.0;
  read_kinematics(l, length, m);
  return m;
}

}  // namespace

double MovingLoadSpec::position(double t) const {
  const double tau = t - entry_time;
  return start + direction() * (speed * tau + 0.5 * acceleration * tau * tau);
}

std::vector<const MovingLoadSpec*> prescribed_loads_at_start(const Scene& sc) {
  std::vector<const MovingLoadSpec*> on;
  for (const auto& l : sc.loads) {
    const double s0 = l.sigma(0.0);
    if (!l.coupled && l.force.norm() > 0.0 && std::isfinite(s0) && s0 >= 0.0 && s0 <= sc.length()) on.push_back(&l);
  }
  return on;
}

double MovingLoadSpec::sigma(double t) const {
  return t < entry_time ? std::numeric_limits<double>::quiet_NaN() : position(t);
}

double MovingLoadSpec::fastest_speed(double length, double t_end) const {
  double t_last = exit_time(length);
  if (t_end >= 0.0) t_last = std::min(t_last, t_end);
  const double at_last = t_last > entry_time && std::isfinite(t_last) ? std::abs(velocity(t_last)) : 0.0;
  return std::max(speed, at_last);
}

double MovingLoadSpec::velocity(double t) const { return direction() * (speed + acceleration * (t - entry_time)); }

double MovingLoadSpec::extent() const {
  if (!train_offsets.empty()) return train_offsets.back();
  if (axle_offsets.empty()) return 0.0;
  return *std::max_element(axle_offsets.begin(), axle_offsets.end()) -
         *std::min_element(axle_offsets.begin(), axle_offsets.end());
}

double MovingLoadSpec::exit_time(double length) const {
  // The distance the leading axle travels until the trailing one reaches the far end.
  return travel_time((direction() > 0 ? length - start : start) + extent());
}

double MovingLoadSpec::travel_time(double d) const {
  const double v = speed, a = acceleration;
  if (!(d > 0.0)) return entry_time;
  if (a == 0.0) return v > 0.0 ? entry_time + d / v : std::numeric_limits<double>::infinity();
  // v tau + a tau^2 / 2 = d, as tau = 2 d / (v + sqrt(v^2 + 2 a d)): no cancellation, and the
  // root by hypot (a > 0) or scaled by v (a < 0) so that v^2 and a d cannot overflow.
  if (a > 0.0) return entry_time + 2.0 * d / (v + std::hypot(v, std::sqrt(2.0) * std::sqrt(a) * std::sqrt(d)));
  if (!(v > 0.0)) return std::numeric_limits<double>::infinity();
  const double r = (2.0 * -a / v) * (d / v);  // 2 |a| d / v^2: it stops before the end when > 1
  if (!(r <= 1.0)) return std::numeric_limits<double>::infinity();
  return entry_time + 2.0 * (d / v) / (1.0 + std::sqrt(1.0 - r));
}

const Param& scene_schema() {
  static const Param root = build_schema();
  return root;
}

[[noreturn]] void fail_at(const Scene& scene, const std::string& key_path, const std::string& expected,
                          const std::string& found) {
  CheckContext(scene.file, "", &scene.tree.marks).fail(key_path, expected, found);
}

namespace {

void read_beam(const ParameterList& b, BeamSpec& beam) {
  beam.length = b.get<double>("length");
  beam.youngs_modulus = b.get<double>("youngs_modulus");
  beam.density = b.get<double>("density");
  beam.section = build_section(b.sublist("section"));
  beam.supports = enum_of<Supports>(b.get<std::string>("supports"));
  beam.modes = b.get<int>("modes");
  beam.quadrature_points = b.get<int>("quadrature_points");
  beam.integrator = enum_of<BeamIntegrator>(b.get<std::string>("integrator"));
  beam.self_weight = b.get<bool>("self_weight");
  if (!b.isSublist("damping")) return;
  const auto& d = b.sublist("damping");
  if (d.isParameter("ratio") || d.isParameter("ratios")) {
    beam.damping = BeamSpec::Damping::ratios;
    beam.damping_ratios = d.isParameter("ratio") ? std::vector<double>{d.get<double>("ratio")}
                                                 : numbers(d, "ratios");
  } else {
    beam.damping = BeamSpec::Damping::rayleigh;
    beam.rayleigh_mass = d.isParameter("mass") ? d.get<double>("mass") : 0.0;
    beam.rayleigh_stiffness = d.isParameter("stiffness") ? d.get<double>("stiffness") : 0.0;
  }
}

void read_rod(const ParameterList& r, RodSpec& rod) {
  rod.length = r.get<double>("length");
  rod.youngs_modulus = r.get<double>("youngs_modulus");
  rod.shear_modulus = r.isParameter("shear_modulus") ? r.get<double>("shear_modulus")
                                                     : rod.youngs_modulus / (2.0 * (1.0 + r.get<double>("poisson_ratio")));
  rod.density = r.get<double>("density");
  rod.section = build_section(r.sublist("section"));
  rod.intrinsic_curvature = vec3_of(r, "intrinsic_curvature");
  rod.strain = enum_of<RodStrain>(r.get<std::string>("model"));
  const double nu = rod.youngs_modulus / (2.0 * rod.shear_modulus) - 1.0;
  rod.shear_coefficient = r.isParameter("shear_coefficient") ? r.get<double>("shear_coefficient")
                                                             : cowper_shear_coefficient(rod.section, nu);
  rod.axial_stiffness = r.isParameter("axial_stiffness") ? r.get<double>("axial_stiffness")
                                                         : rod.youngs_modulus * rod.section.area;
  rod.shear_stiffness = r.isParameter("shear_stiffness")
                            ? r.get<double>("shear_stiffness")
                            : rod.shear_coefficient * rod.shear_modulus * rod.section.area;
  if (!r.isSublist("damping")) return;
  const auto& d = r.sublist("damping");
  rod.damping_axial = d.get<double>("axial");
  rod.damping_shear = d.get<double>("shear");
  rod.damping_bending = d.get<double>("bending");
  rod.damping_torsion = d.get<double>("torsion");
}

// An end as its type declares it (traverse/core/end_types.hpp): each parameter into its
// member of EndSpec, a direction normalised.
void read_end(const ParameterList& e, EndSpec& spec) {
  spec.type = enum_of<EndType>(e.get<std::string>("type"));
  for (const auto& p : end_type_declarations().at(static_cast<std::size_t>(spec.type)).parameters) {
    if (!e.isParameter(p.key)) continue;
    if (p.vector) spec.*p.vector = p.direction ? vec3_of(e, p.key).normalized() : vec3_of(e, p.key);
    else spec.*p.number = e.get<double>(p.key);
  }
}

void read_scheme(const ParameterList& s, SchemeSpec& scheme) {
  scheme.rho_inf = s.get<double>("rho_inf");
  scheme.rho_inf_space = s.get<double>("rho_inf_space");
  scheme.planar = enum_of<PlanarMode>(s.get<std::string>("planar"));
  if (s.isSublist("parameters")) {
    const auto& a = s.sublist("parameters");
    scheme.explicit_parameters = true;
    scheme.as = a.get<double>("as");
    scheme.bs = a.get<double>("bs");
    scheme.gs = a.get<double>("gs");
    scheme.at = a.get<double>("at");
    scheme.bt = a.get<double>("bt");
    scheme.gt = a.get<double>("gt");
  }
}

void read_initial_state(const ParameterList& init, Scene& sc) {
  sc.initial_state.type = enum_of<InitialStateType>(init.get<std::string>("type"));
  if (init.isParameter("file")) sc.initial_state.file = init.get<std::string>("file");
  sc.initial_state.state = init.get<std::string>("state");
  sc.initial_state.loaded = init.get<bool>("loaded");
  if (init.isParameter("end_to_end")) {
    sc.initial_state.end_to_end = init.get<double>("end_to_end");
    if (sc.initial_state.end_to_end >= sc.rod.length)
      fail_at(sc, "initial_state.end_to_end", "a distance shorter than the rod, < " + format_number(sc.rod.length),
              format_number(sc.initial_state.end_to_end));
  }
}

ContinuationProbeSpec read_continuation_probe(const std::string& name, const ParameterList& q, const Scene& sc) {
  ContinuationProbeSpec ps;
  ps.name = name;
  ps.type = enum_of<ContinuationProbeType>(q.get<std::string>("type"));
  if (ps.type == ContinuationProbeType::point) {
    ps.at = q.get<double>("at");
    ps.quantity = enum_of<Quantity>(q.get<std::string>("quantity"));
    const auto comp = q.get<std::string>("component");
    ps.frame = (comp == "1" || comp == "2" || comp == "3") ? Frame::body : Frame::fixed;
    ps.component = comp == "x" || comp == "1" ? 0 : comp == "y" || comp == "2" ? 1 : 2;
    if (ps.at > sc.rod.length)
      fail_at(sc, "continuation.probes." + ps.name + ".at", "a position on the rod, in [0, " +
              format_number(sc.rod.length) + "]", format_number(ps.at));
  }
  return ps;
}

void read_continuation(const ParameterList& c, std::size_t num_loads, Scene& sc) {
  auto& cs = sc.continuation;
  cs.enabled = true;
  cs.parameter = enum_of<ContinuationParameter>(c.get<std::string>("parameter"));
  cs.start_given = c.isParameter("start");
  if (cs.start_given) cs.start = c.get<double>("start");
  cs.stop = c.get<double>("stop");
  cs.step = c.get<double>("step");
  cs.min_step = c.get<double>("min_step");
  cs.max_step = c.isParameter("max_step") ? c.get<double>("max_step") : 10.0 * cs.step;
  cs.method = enum_of<ContinuationMethod>(c.get<std::string>("method"));
  cs.max_steps = c.get<int>("max_steps");
  cs.stability = c.get<bool>("stability");
  cs.eigenvalues = c.get<int>("eigenvalues");
  cs.switch_branches = c.get<bool>("switch_branches");
  cs.branch_amplitude = c.get<double>("branch_amplitude");
  const auto& probes = c.sublist("probes");
  for (const auto& entry : probes)
    cs.probes.push_back(read_continuation_probe(entry.first, probes.sublist(entry.first), sc));
  if ((cs.parameter == ContinuationParameter::load_position || cs.parameter == ContinuationParameter::load_magnitude) &&
      num_loads != 1)
    fail_at(sc, "continuation.parameter", "exactly one load in the scene to continue in " + name_of(cs.parameter),
            std::to_string(num_loads) + " loads");
}

// The rod's sections: rod, ends, scheme, initial_state, continuation.
void read_rod_scene(const ParameterList& p, Scene& sc) {
  read_rod(p.sublist(kRod), sc.rod);
  read_end(p.sublist("ends").sublist("left"), sc.left);
  read_end(p.sublist("ends").sublist("right"), sc.right);
  read_scheme(p.sublist("scheme"), sc.scheme);
  read_initial_state(p.sublist("initial_state"), sc);
  if (p.isSublist("continuation")) read_continuation(p.sublist("continuation"), p.sublist("loads").numParams(), sc);
}

// coupled_mass: what is implemented so far (docs/beam.md, docs/rod.md "Coupled mass"); every
// other combination is refused here rather than run wrongly.
void check_coupled_masses(Scene& sc) {
  const MovingLoadSpec* coupled = nullptr;
  for (const auto& l : sc.loads) {
    if (!l.coupled) continue;
    const std::string k = "loads." + l.name;
    if (sc.model == Model::Rod && sc.continuation.enabled)
      fail_at(sc, k + ".type", "a moving_mass or moving_force in a continuation scene (a coupled_mass moves by "
              "itself: dynamics only)", "coupled_mass");
    if (coupled)
      fail_at(sc, k + ".type", "at most one coupled_mass per scene (not yet supported: several)",
              "a second one besides '" + coupled->name + "'");
    coupled = &l;
  }
  if (!coupled) return;
  if (sc.beam.damping != BeamSpec::Damping::none && sc.model == Model::Beam)
    fail_at(sc, "beam.damping", "no structural damping with a coupled_mass (not yet supported)", "a damping section");
  if (sc.loads.size() > 1)
    fail_at(sc, "loads." + coupled->name + ".type",
            "a coupled_mass as the only load of its scene (not yet supported: together with other loads)",
            std::to_string(sc.loads.size()) + " loads");
}

// A sprung_mass on the rod: the only load, on the rod from the start (the rod's coupled run).
void check_rod_sprung_mass(const Scene& sc, const MovingLoadSpec& l) {
  const std::string k = "loads." + l.name;
  if (sc.loads.size() > 1)
    fail_at(sc, k + ".type", "a sprung_mass on the rod as the only load of its scene (not yet supported: together "
            "with other loads)", std::to_string(sc.loads.size()) + " loads");
  if (sc.continuation.enabled)
    fail_at(sc, k + ".type", "a moving_mass or moving_force in a continuation scene (a sprung_mass: dynamics only)",
            "sprung_mass");
  if (l.entry_time != 0.0)
    fail_at(sc, k + ".entry_time", "0 for a sprung_mass on the rod (it starts on the rod)", format_number(l.entry_time));
  if (sc.time.adaptive.enabled)
    fail_at(sc, "time.adaptive", "fixed steps with a sprung_mass (adaptive steps are not supported)", "a section");
}

// vehicle, axle_train: beam scenes only, sprung_mass also on the rod; vehicles on suspensions
// only with each other.
void check_vehicles(const Scene& sc) {
  const MovingLoadSpec* suspended = nullptr;
  const MovingLoadSpec* other = nullptr;
  for (const auto& l : sc.loads) {
    const bool vehicle_type = l.suspended() || l.type == LoadType::axle_train;
    if (vehicle_type && sc.model == Model::Rod && l.type == LoadType::sprung_mass) {
      check_rod_sprung_mass(sc, l);
      continue;
    }
    if (vehicle_type && sc.model != Model::Beam)
      fail_at(sc, "loads." + l.name + ".type", "a load type of the rod (moving_mass, moving_force, coupled_mass, "
              "sprung_mass; vehicles and axle trains ride on the beam model)", "'" + name_of(l.type) + "'");
    (l.suspended() ? suspended : other) = &l;
  }
  if (suspended && other)
    fail_at(sc, "loads." + other->name + ".type", "only sprung_mass and vehicle loads together with the sprung_mass or "
            "vehicle '" + suspended->name + "' (not yet supported: mixed with other loads)", "'" + name_of(other->type) + "'");
  if (suspended && sc.time.adaptive.enabled)
    fail_at(sc, "time.adaptive", "fixed steps with a sprung_mass or vehicle (adaptive steps are not supported)",
            "a section");
}

// time.adaptive, when given.
void read_adaptive(const ParameterList& t, Scene& sc) {
  if (!t.isSublist("adaptive")) return;
  const ParameterList& a = t.sublist("adaptive");
  AdaptiveSpec& s = sc.time.adaptive;
  s.enabled = true;
  s.tolerance = a.get<double>("tolerance");
  static const char* const kGroups[5] = {"position", "orientation", "u", "omega", "kappa"};
  const auto on = words(a, "on");
  for (int g = 0; g < 5; ++g) {
    s.controlled[g] = std::find(on.begin(), on.end(), kGroups[g]) != on.end();
    s.absolute[g] = a.get<double>(std::string("absolute_") + kGroups[g]);
  }
  if (on.empty()) fail_at(sc, "time.adaptive.on", "at least one quantity", "[]");
  for (int g = 2; g < 5; ++g)  // the state groups have no scale floor: a start from rest needs an absolute tolerance
    if (s.controlled[g] && s.absolute[g] == 0.0)
      fail_at(sc, std::string("time.adaptive.absolute_") + kGroups[g],
              std::string("a value > 0 when time.adaptive.on includes ") + kGroups[g] +
                  " (its relative scale is zero at a start from rest)", "0");
  s.dt_min = a.isParameter("dt_min") ? a.get<double>("dt_min") : 0.0;
  s.dt_max = a.isParameter("dt_max") ? a.get<double>("dt_max") : 0.0;
  s.growth = a.get<double>("growth");
  s.shrink = a.get<double>("shrink");
  s.safety = a.get<double>("safety");
  s.newton_target = a.get<int>("newton_target");
  s.land_on_nodes = a.get<bool>("land_on_nodes");
  if (sc.continuation.enabled)
    fail_at(sc, "time.adaptive", "no adaptive time stepping in a continuation run (it has no time steps)", "a section");
}

// time: dt and end, with 'auto' resolved where the scene alone decides it.
void read_time(const ParameterList& t, Scene& sc) {
  sc.time.dt_auto = t.isType<std::string>("dt");
  if (!sc.time.dt_auto) sc.time.dt = t.get<double>("dt");
  sc.time.end_auto = t.isType<std::string>("end");
  if (!sc.time.end_auto) sc.time.end = t.get<double>("end");
  const bool coupled = std::any_of(sc.loads.begin(), sc.loads.end(), [](const MovingLoadSpec& l) { return l.coupled; });
  if (coupled && sc.time.end_auto) {  // ends at the first event, at the latest at auto_limit
    sc.time.end_auto = false;
    sc.time.end_at_event = true;
    sc.time.end = t.get<double>("auto_limit");
  }
  if (sc.time.end_auto && !sc.continuation.enabled) {
    if (sc.loads.empty()) fail_at(sc, "time.end", "a number when the scene has no loads ('auto' ends when the last load leaves)", "auto");
    for (const auto& l : sc.loads)
      if (!std::isfinite(l.exit_time(sc.length())))
        fail_at(sc, "time.end", "a number: with 'auto' every load must leave the structure, but load '" + l.name +
                "' stops before it does", "auto");
  }
  read_adaptive(t, sc);
  if (sc.model == Model::Rod && sc.time.dt_auto && !sc.continuation.enabled) {
    double v = 0.0;
    for (const auto& l : sc.loads) v = std::max(v, l.fastest_speed(sc.length(), sc.time.end_auto ? -1.0 : sc.time.end));
    if (!(v > 0.0)) fail_at(sc, "time.dt", "a number when no load moves (auto is ds / v)", "auto");
    sc.time.dt = sc.mesh.ds / v;
  }
}

void read_output(const ParameterList& o, const std::string& file_name, OutputSpec& out) {
  out.file = o.get<std::string>("file");
  if (out.file == "auto") out.file = std::filesystem::path(file_name).stem().string() + ".h5";
  out.every_auto = o.isType<std::string>("every");
  out.every = out.every_auto ? 1 : o.get<int>("every");
  out.restart_interval = o.get<double>("restart_interval");
  out.flush_interval = o.get<double>("flush_interval");
  out.progress_interval = o.get<double>("progress_interval");
  const auto& probes = o.sublist("probes");
  for (const auto& entry : probes) {
    const auto& pr = probes.sublist(entry.first);
    OutputProbeSpec ps;
    ps.name = entry.first;
    ps.type = enum_of<ProbeType>(pr.get<std::string>("type"));
    ps.at = pr.get<double>("at");
    if (ps.type == ProbeType::point) {
      ps.quantity = enum_of<Quantity>(pr.get<std::string>("quantity"));
      ps.frame = enum_of<Frame>(pr.get<std::string>("frame"));
    }
    out.probes.push_back(ps);
  }
  for (const auto& f : words(o, "fields")) out.fields.push_back(enum_of<Field>(f));
}

}  // namespace

Scene parse_scene(const std::string& yaml_text, const std::string& file_name, const std::vector<std::string>& overrides) {
  Scene sc;
  sc.file = file_name;
  sc.tree = validate_yaml(yaml_text, file_name, overrides, scene_schema());
  const ParameterList& p = *sc.tree.params;
  const std::string model = p.get<std::string>("model");
  sc.title = p.get<std::string>("title");
  sc.gravity = p.get<double>("gravity");
  if (model == kBeam) {
    sc.model = Model::Beam;
    read_beam(p.sublist(kBeam), sc.beam);
  } else if (model == kRod) {
    sc.model = Model::Rod;
    read_rod_scene(p, sc);
  } else {
    throw std::logic_error("parse_scene: unknown model " + model);
  }
  const double structure_mass = sc.model == Model::Beam ? sc.beam.mass() : sc.rod.mass();

  const auto& m = p.sublist("mesh");
  if (m.isParameter("ds")) sc.mesh.nodes = static_cast<int>(std::lround(sc.length() / m.get<double>("ds"))) + 1;
  else sc.mesh.nodes = m.isParameter("nodes") ? m.get<int>("nodes") : 101;
  sc.mesh.ds = sc.length() / (sc.mesh.nodes - 1);

  const auto& loads = p.sublist("loads");
  for (const auto& entry : loads)
    sc.loads.push_back(build_load(entry.first, loads.sublist(entry.first), structure_mass, sc.length(), sc.gravity));
  check_coupled_masses(sc);
  if (sc.model == Model::Rod && sc.initial_state.loaded) {
    if (sc.continuation.enabled)
      fail_at(sc, "initial_state.loaded", "false in a continuation scene (the statics start from the unloaded arch "
              "and continue in the load)", "true");
    const size_t on = prescribed_loads_at_start(sc).size();
    if (on != 1)
      fail_at(sc, "initial_state.loaded",
              "exactly one prescribed load (a moving force or mass, not coupled) on the arch at t = 0",
              std::to_string(on) + " such loads");
  }
  read_time(p.sublist("time"), sc);
  check_vehicles(sc);
  read_output(p.sublist("output"), file_name, sc.output);
  for (const auto& pr : sc.output.probes)
    if (pr.type == ProbeType::acceleration && std::any_of(sc.loads.begin(), sc.loads.end(),
                                                          [](const MovingLoadSpec& l) { return l.coupled; }))
      fail_at(sc, "output.probes." + pr.name + ".type", "a deflection probe with a coupled_mass (acceleration: not yet "
              "supported there)", "'acceleration'");
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

const Teuchos::ParameterList& Scene::solver_parameters() const {
  if (!tree.params) throw std::logic_error("Scene::solver_parameters: the scene was not validated (parse_scene)");
  return tree.params->sublist("solver");
}

bool Scene::has(const std::string& key_path) const {
  const ParameterList* list = tree.params.get();
  if (!list) return false;
  std::string::size_type from = 0, dot = 0;
  while ((dot = key_path.find('.', from)) != std::string::npos) {
    const std::string part = key_path.substr(from, dot - from);
    if (!list->isSublist(part)) return false;
    list = &list->sublist(part);
    from = dot + 1;
  }
  return list->isParameter(key_path.substr(from));
}

std::string describe_scene(const Scene& scene, bool with_comments) {
  return describe(scene.tree, scene_schema(), with_comments);
}

std::string describe_types() {
  std::ostringstream os;
  for (const auto& reg : {section_types(), end_types(), load_types(), probe_types(), continuation_probe_types()}) {
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
