#include "traverse/setup/beam_fields.hpp"

#include <stdexcept>

#include "traverse/core/comm.hpp"

namespace traverse::setup {

beam::ModalDamping beam_damping(const scene::BeamSpec& b) {
  beam::ModalDamping d;
  switch (b.damping) {
    case scene::BeamSpec::Damping::none: break;
    case scene::BeamSpec::Damping::ratios:
      d.kind = beam::ModalDamping::Kind::Ratios;
      d.ratios = b.damping_ratios;
      break;
    case scene::BeamSpec::Damping::rayleigh:
      d.kind = beam::ModalDamping::Kind::Rayleigh;
      d.mass = b.rayleigh_mass;
      d.stiffness = b.rayleigh_stiffness;
      break;
    default: throw std::logic_error("beam_damping: unknown kind");
  }
  return d;
}

void declare_beam_probe(output::Writer& w, const scene::OutputProbeSpec& pr) {
  const std::string at = " at x = " + scene::format_number(pr.at) + " m";
  if (pr.type == scene::ProbeType::acceleration)
    w.add_probe({pr.name, 1, "m/s^2", "transverse acceleration w_tt (positive up, +j)" + at, {}});
  else
    w.add_probe({pr.name, 1, "m", "transverse deflection w (positive up, +j)" + at, {}});
}

BeamFields::BeamFields(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
    : EI_(p.EI) {
  const int rank = par::rank(comm), ranks = par::size(comm);
  const size_t n_nodes = static_cast<size_t>(sc.mesh.nodes);
  layout_.global_count = n_nodes;
  layout_.first = n_nodes * static_cast<size_t>(rank) / static_cast<size_t>(ranks);
  layout_.count = n_nodes * static_cast<size_t>(rank + 1) / static_cast<size_t>(ranks) - layout_.first;
  for (size_t k = 0; k < layout_.count; ++k) layout_.s.push_back(p.quadrature_nodes[layout_.first + k]);
  for (const auto f : sc.output.fields) {
    switch (f) {
      case scene::Field::deflection: break;  // always written
      case scene::Field::slope: slope_ = true; break;
      case scene::Field::bending_moment: moment_ = true; break;
      default: throw std::logic_error("BeamFields: a rod field in a beam scene");
    }
  }
  const Eigen::Index n = modes.size();
  phi_.assign(layout_.count, VecX(n));
  dphi_.assign(layout_.count, VecX(n));
  ddphi_.assign(layout_.count, VecX(n));
  for (size_t j = 0; j < layout_.count; ++j) modes.evaluate(layout_.s[j], phi_[j], dphi_[j], ddphi_[j]);
  values_.emplace_back(layout_.count);
  values_.emplace_back(3 * layout_.count);
  if (slope_) values_.emplace_back(layout_.count);
  if (moment_) values_.emplace_back(layout_.count);
}

std::vector<std::string> BeamFields::names() const {
  std::vector<std::string> names{"deflection", "position"};  // always: the sidecar shows the deflected beam
  if (slope_) names.push_back("slope");
  if (moment_) names.push_back("bending_moment");
  return names;
}

void BeamFields::declare(output::Writer& w) const {
  w.add_field({"deflection", 1, "m", "transverse deflection w (positive up, +j)", {"w"}, false, false});
  w.add_field({"position", 3, "m", "deformed position (x, w, 0): the beam along x, w along y", {"x", "y", "z"}, true});
  if (slope_) w.add_field({"slope", 1, "1", "slope dw/dx", {"w_x"}, false});
  if (moment_) w.add_field({"bending_moment", 1, "N m", "bending moment E I d2w/dx2", {"M"}, false});
}

void BeamFields::evaluate(const VecX& Y) {
  auto& w = values_[0];
  auto& pos = values_[1];
  for (size_t j = 0; j < layout_.count; ++j) {
    w[j] = phi_[j].dot(Y);
    pos[3 * j] = layout_.s[j];
    pos[3 * j + 1] = w[j];
    pos[3 * j + 2] = 0.0;
  }
  size_t f = 2;
  if (slope_) {
    auto& v = values_[f++];
    for (size_t j = 0; j < layout_.count; ++j) v[j] = dphi_[j].dot(Y);
  }
  if (moment_) {
    auto& v = values_[f++];
    for (size_t j = 0; j < layout_.count; ++j) v[j] = EI_ * ddphi_[j].dot(Y);
  }
}

}  // namespace traverse::setup
