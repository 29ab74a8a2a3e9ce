// Scene -> beam::BeamProblem, then the run with its output.
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "traverse/output/restart.hpp"
#include "run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/beam/beam_simulation.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

beam::Support support_of(scene::Supports s) {
  using S = scene::Supports;
  switch (s) {
    case S::simply_supported: return beam::Support::SimplySupported;
    case S::clamped_free: return beam::Support::ClampedFree;
    case S::clamped_clamped: return beam::Support::ClampedClamped;
    case S::clamped_pinned: return beam::Support::ClampedPinned;
    default: throw std::logic_error("run_beam: unknown supports");
  }
}

}  // namespace

void run_beam(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const auto& b = sc.beam;

  beam::BeamProblem p;
  p.length = b.length;
  p.EI = b.youngs_modulus * b.section.I1;
  p.rhoA = b.density * b.section.area;
  p.support = support_of(b.supports);
  p.n_modes = b.modes;
  p.quadrature_nodes.resize(static_cast<size_t>(sc.mesh.nodes));
  for (int j = 0; j < sc.mesh.nodes; ++j) p.quadrature_nodes[static_cast<size_t>(j)] = j * sc.mesh.ds;
  p.quadrature_nodes.back() = b.length;
  p.gauss_points = b.quadrature_points;
  p.gravity = sc.gravity;
  p.self_weight = true;
  p.initial_state = beam::InitialState::Static;

  double t_end = 0.0, v_max = 0.0;
  for (const auto& l : sc.loads) {
    beam::MovingLoad m;
    m.kind = l.inertia ? beam::LoadKind::Mass : beam::LoadKind::Force;
    m.mass = l.mass;
    m.force = l.force.y();  // vertical, positive up (validated: no other components)
    m.entry = l.entry == scene::Entry::left ? beam::BeamEnd::Left : beam::BeamEnd::Right;
    m.direction = l.direction();
    m.speed = l.speed;
    m.acceleration = l.acceleration;
    m.entry_time = l.entry_time;
    m.start = l.start;
    p.loads.push_back(m);
    const double te = l.exit_time(b.length);
    if (std::isfinite(te)) t_end = std::max(t_end, te);
    v_max = std::max({v_max, l.speed, std::abs(l.velocity(std::isfinite(te) ? te : l.entry_time))});
  }
  p.t_start = 0.0;
  p.t_end = sc.time.end_auto ? t_end : sc.time.end;
  if (sc.time.dt_auto) {
    const beam::UniformModes modes(p.support, p.n_modes, p.length, p.EI, p.rhoA);
    const double omega_max = modes.circular_frequencies().maxCoeff();
    double dt = 2.0 * constants::pi / omega_max / 20.0;
    if (v_max > 0.0) dt = std::min(dt, sc.mesh.ds / v_max);
    p.dt = dt;
  } else {
    p.dt = sc.time.dt;
  }
  p.integrator = b.integrator == scene::BeamIntegrator::newmark ? beam::Integrator::Newmark : beam::Integrator::RK4;
  p.output_every = sc.output.every;

  // Output: nodes split over the ranks in contiguous ranges (the beam itself is solved,
  // replicated, on every rank: it is a small dense system).
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const size_t n_nodes = static_cast<size_t>(sc.mesh.nodes);
  output::NodeLayout layout;
  layout.global_count = n_nodes;
  layout.first = n_nodes * static_cast<size_t>(rank) / static_cast<size_t>(ranks);
  layout.count = n_nodes * static_cast<size_t>(rank + 1) / static_cast<size_t>(ranks) - layout.first;
  for (size_t k = 0; k < layout.count; ++k) layout.s.push_back(p.quadrature_nodes[layout.first + k]);

  // Restart (docs/reliability.md): the beam is re-integrated from t = 0 (BeamSimulation
  // cannot be set to a stored state); the output steps the file already holds are checked
  // against the replay (same values to round-off, else the scene or program differ), then
  // rewritten, and the run continues.
  std::vector<std::string> probe_names, field_names;
  for (const auto& pr : sc.output.probes) probe_names.push_back(pr.name);
  for (const auto& l : sc.loads) {
    probe_names.push_back(l.name + "_position");
    probe_names.push_back(l.name + "_deflection");
  }
  field_names = {"deflection", "position"};  // always written: the sidecar shows the deflected beam
  for (const auto f : sc.output.fields) {
    if (f != scene::Field::deflection) field_names.push_back(scene::name_of(f));
  }
  std::size_t kept = 0;  // output steps of the restarted file to check against the replay
  std::vector<double> old_time;
  std::vector<output::Series> old_probes;
  if (opt.restart) {
    const std::string source = output::restart_source(opt.output);
    output::check_restart_outputs(source, probe_names, field_names);
    try {
      output::Reader r(source);
      kept = r.steps_written();
      old_time = r.time();
      for (const auto& n : probe_names) old_probes.push_back(r.probe(n));
    } catch (const output::OutputError& e) {
      throw UsageError{"--restart: cannot read " + source + " (" + e.what() + ")"};
    }
    output::move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, layout,
                        std::max<size_t>(1, sc.loads.size()));

  for (const auto& pr : sc.output.probes)
    writer.add_probe({pr.name, 1, "m", "transverse deflection w (positive up, +j) at x = " +
                                           scene::format_number(pr.at) + " m", {}});
  for (const auto& l : sc.loads) {
    writer.add_probe({l.name + "_position", 1, "m", "position x(t) of load '" + l.name + "' along the beam", {}});
    writer.add_probe({l.name + "_deflection", 1, "m",
                      "deflection w(x(t), t) under load '" + l.name + "' (NaN while it is off the beam)", {}});
  }
  bool want_w = true, want_slope = false, want_moment = false;
  for (const auto f : sc.output.fields) {
    switch (f) {
      case scene::Field::deflection: want_w = true; break;
      case scene::Field::slope: want_slope = true; break;
      case scene::Field::bending_moment: want_moment = true; break;
      default: throw std::logic_error("run_beam: a rod field in a beam scene");
    }
  }
  if (want_w) {
    writer.add_field({"deflection", 1, "m", "transverse deflection w (positive up, +j)", {"w"}, false, false});
    writer.add_field({"position", 3, "m", "deformed position (x, w, 0): the beam along x, w along y", {"x", "y", "z"}, true});
  }
  if (want_slope) writer.add_field({"slope", 1, "1", "slope dw/dx", {"w_x"}, false});
  if (want_moment) writer.add_field({"bending_moment", 1, "N m", "bending moment E I d2w/dx2", {"M"}, false});

  beam::BeamSimulation sim(p);
  const size_t nl = sc.loads.size();
  std::vector<std::vector<double>> probes(sc.output.probes.size() + 2 * nl, std::vector<double>(1));
  std::vector<std::vector<double>> fields;
  if (want_w) fields.emplace_back(layout.count), fields.emplace_back(3 * layout.count);
  if (want_slope) fields.emplace_back(layout.count);
  if (want_moment) fields.emplace_back(layout.count);
  std::vector<double> sigma(std::max<size_t>(1, nl), std::numeric_limits<double>::quiet_NaN());
  const Eigen::Index n = sim.modes().size();
  // The modes at the local output nodes, evaluated once (w = phi . Y as in BeamSnapshot).
  std::vector<VecX> node_phi(layout.count, VecX(n)), node_dphi(layout.count, VecX(n)), node_ddphi(layout.count, VecX(n));
  for (size_t j = 0; j < layout.count; ++j) sim.modes().evaluate(layout.s[j], node_phi[j], node_dphi[j], node_ddphi[j]);

  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end);
  long outputs = 0;
  // /restart of a beam run: the modal state (Y then Y') and [t, steps taken, output steps]
  // of the last output step, written once when the run stops (a restart re-integrates from
  // t = 0 and needs only the output steps; these arrays document the state and are for
  // a future BeamSimulation::set_state).
  std::vector<double> restart_state, restart_meta;
  auto store_restart = [&]() {
    if (restart_meta.empty()) return;
    writer.write_restart(restart_meta[0],
                         {{"modal_state", output::RestartDistribution::replicated, 1, output::DoubleView(restart_state)},
                          {"meta", output::RestartDistribution::replicated, 1, output::DoubleView(restart_meta)}});
  };
  auto observe = [&](const beam::BeamSnapshot& s) {
    if (!s.Y.allFinite() || !s.Ydot.allFinite()) {
      std::ostringstream os;
      os << "beam solver: the modal state is not finite at t = " << s.t << " s (after " << sim.steps_taken()
         << " steps of dt = " << p.dt << " s with " << scene::name_of(b.integrator)
         << "); reduce time.dt or use beam.integrator: newmark";
      throw NumericsError(os.str());
    }
    size_t k = 0;
    for (const auto& pr : sc.output.probes) probes[k++][0] = s.deflection(pr.at);
    for (size_t i = 0; i < nl; ++i) {
      sigma[i] = s.load_position(i);
      probes[k++][0] = s.load_position(i);
      probes[k++][0] = s.load_deflection(i);
    }
    size_t f = 0;
    if (want_w) {
      auto& w = fields[f++];
      auto& pos = fields[f++];
      for (size_t j = 0; j < layout.count; ++j) {
        w[j] = node_phi[j].dot(s.Y);
        pos[3 * j] = layout.s[j];
        pos[3 * j + 1] = w[j];
        pos[3 * j + 2] = 0.0;
      }
    }
    if (want_slope) {
      auto& v = fields[f++];
      for (size_t j = 0; j < layout.count; ++j) v[j] = node_dphi[j].dot(s.Y);
    }
    if (want_moment) {
      auto& v = fields[f++];
      for (size_t j = 0; j < layout.count; ++j) v[j] = p.EI * node_ddphi[j].dot(s.Y);
    }
    if (static_cast<std::size_t>(outputs) < kept) {  // restart: the replay must reproduce the file
      const auto o = static_cast<std::size_t>(outputs);
      auto differs = [](double a, double b) {
        return !(a == b || (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)));
      };
      std::string bad;
      if (differs(old_time[o], s.t)) bad = "time " + scene::format_number(old_time[o]) + " vs " + scene::format_number(s.t);
      for (size_t q = 0; bad.empty() && q < probes.size(); ++q)
        if (differs(old_probes[q].values[o], probes[q][0]))
          bad = "probe " + probe_names[q] + " = " + scene::format_number(old_probes[q].values[o]) + " vs " +
                scene::format_number(probes[q][0]);
      if (!bad.empty())
        throw UsageError{"--restart " + opt.output + ": re-integrating the beam does not reproduce output step " +
                         std::to_string(o) + " (" + bad + "); the scene or the program differ from the run being restarted"};
    }
    std::vector<output::DoubleView> views(fields.begin(), fields.end());
    writer.write_step(s.t, sigma, probes, views);
    ++outputs;
    if (opt.restart && static_cast<std::size_t>(outputs) == kept) output::remove_restart_source(opt.output, comm);
    // Kept for the restart group written when the run stops (store_restart).
    restart_state.assign(s.Y.data(), s.Y.data() + s.Y.size());
    restart_state.insert(restart_state.end(), s.Ydot.data(), s.Ydot.data() + s.Ydot.size());
    restart_meta = {s.t, static_cast<double>(sim.steps_taken()), static_cast<double>(outputs)};
    progress.update(s.t, sim.steps_taken());
    if (s.t < p.t_end) {
      if (const int sig = interrupt_requested(comm)) {
        progress.done();
        std::ostringstream os;
        os.precision(12);
        os << "interrupted at t = " << s.t << " s (time step " << sim.steps_taken() << ", " << signal_name(sig)
           << "); " << writer.steps_written() << " output steps written; continue with traverse run --restart "
           << opt.output;
        store_restart();
        writer.fail(os.str());
        throw Interrupted(sig, opt.output, os.str(), os.str());
      }
    }
  };
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    sim.run(observe);
  } catch (const NumericsError& e) {
    progress.done();
    store_restart();
    writer.fail(e.what());
    throw;
  }
  progress.done();
  store_restart();
  writer.finish();
  if (opt.restart && static_cast<std::size_t>(outputs) < kept) output::remove_restart_source(opt.output, comm);  // shorter run
  if (rank == 0 && !opt.quiet) {
    std::printf("beam scene '%s': %d modes, %ld steps of dt = %.4g s (%s) to t = %.6g s; %ld output steps -> %s; "
                "time stepping %.3f s (wall, output included)\n",
                sc.file.c_str(), b.modes, sim.steps_taken(), p.dt, scene::name_of(b.integrator).c_str(), p.t_end, outputs,
                opt.output.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  }
}

}  // namespace traverse::app
