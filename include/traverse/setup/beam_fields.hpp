#pragma once
// The fields of a beam run, shared by the beam with moving loads (run_beam.cpp) and the beam
// with a coupled mass (run_beam_coupled.cpp): this rank's contiguous range of output nodes,
// the modes there (evaluated once), and the arrays written at each output step: the
// deflection and the deflected shape (x, w, 0) always, slope and bending moment on request.
#include <mpi.h>

#include <string>
#include <vector>

#include "traverse/beam/beam_problem.hpp"
#include "traverse/beam/mode_set.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::setup {

/// The beam's structural damping of a scene (beam.damping).
beam::ModalDamping beam_damping(const scene::BeamSpec& b);

/// Declares an output probe of a beam scene (deflection [m] or acceleration [m/s^2] at a point).
void declare_beam_probe(output::Writer& w, const scene::OutputProbeSpec& probe);

class BeamFields {
 public:
  BeamFields(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm);
  const output::NodeLayout& layout() const { return layout_; }
  std::vector<std::string> names() const;
  void declare(output::Writer& w) const;
  /// The arrays at modal coordinates Y.
  void evaluate(const VecX& Y);
  std::vector<output::DoubleView> views() const { return {values_.begin(), values_.end()}; }

 private:
  double EI_;
  output::NodeLayout layout_;
  bool slope_ = false, moment_ = false;
  std::vector<VecX> phi_, dphi_, ddphi_;
  std::vector<std::vector<double>> values_;
};

}  // namespace traverse::setup
