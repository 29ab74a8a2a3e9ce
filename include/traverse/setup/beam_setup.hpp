#pragma once
// From a beam scene to the beam module's models: the problem (structure, loads, time grid),
// the coupled mass and the vehicles on suspensions.
#include "traverse/beam/beam_problem.hpp"
#include "traverse/beam/coupled_mass_beam.hpp"
#include "traverse/beam/vehicle_beam.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/setup/run_checks.hpp"

namespace traverse::setup {

/// The beam problem of a scene on the time grid and output stride of its checked run
/// plan (run_limits.hpp: dt auto is a twentieth of the highest mode's period, at most the time
/// a load needs to cross one mesh cell; end auto is when the last load leaves; output.every
/// auto keeps kBeamOutputsPerPeriod outputs per period of the highest mode).
beam::BeamProblem beam_problem(const scene::Scene& sc, const CheckedRun& checked);

/// The beam's coupled mass of a scene load (a mass that moves by itself: drive, resistance,
/// friction, contact).
beam::CoupledMass coupled_mass(const scene::MovingLoadSpec& l);

/// The vehicle of a scene load on suspensions (body, pitch inertia, axles, wheels, motion).
beam::Vehicle vehicle(const scene::MovingLoadSpec& l);

}  // namespace traverse::setup
