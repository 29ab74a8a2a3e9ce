#include "traverse/beam/moving_load.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace traverse::beam {

double MovingLoad::inertial_mass() const {
  switch (kind) {
    case LoadKind::Mass: return mass;
    case LoadKind::Force: return 0.0;
    default: throw std::invalid_argument("MovingLoad: unknown kind");
  }
}

LoadKinematics::LoadKinematics(const MovingLoad& load, double length)
    : L_(length),
      x0_(0.0),
      dir_(static_cast<double>(load.direction)),
      v0_(load.speed),
      acc_(load.direction * load.acceleration),
      t_entry_(load.entry_time) {
  if (load.direction != 1 && load.direction != -1)
    throw std::invalid_argument("MovingLoad: direction must be +1 or -1");
  switch (load.entry) {
    case BeamEnd::Left:
      x0_ = 0.0;
      if (load.direction != 1) throw std::invalid_argument("MovingLoad: from x = 0 direction must be +1");
      break;
    case BeamEnd::Right:
      x0_ = length;
      if (load.direction != -1) throw std::invalid_argument("MovingLoad: from x = L direction must be -1");
      break;
    default:
      throw std::invalid_argument("MovingLoad: unknown entry end");
  }
  if (load.start) {
    if (!(*load.start >= 0.0 && *load.start <= length))
      throw std::invalid_argument("MovingLoad: start must lie on the beam, in [0, L]");
    x0_ = *load.start;
  }
  if (load.speed < 0) throw std::invalid_argument("MovingLoad: speed must be >= 0 (use direction)");
  if (load.mass < 0) throw std::invalid_argument("MovingLoad: mass must be >= 0");
}

double LoadKinematics::position(double t) const {
  const double tau = t - t_entry_;
  return x0_ + dir_ * (v0_ * tau + 0.5 * dir_ * acc_ * tau * tau);
}

double LoadKinematics::velocity(double t) const {
  return dir_ * v0_ + acc_ * (t - t_entry_);
}

bool LoadKinematics::on_beam(double t) const {
  if (t < t_entry_) return false;
  const double x = position(t);
  return x >= 0.0 && x <= L_;
}

std::vector<double> LoadKinematics::events(double t0, double t1) const {
  std::vector<double> ev;
  auto add = [&](double t) {
    if (t > t0 && t < t1) ev.push_back(t);
  };
  add(t_entry_);
  // The load crosses x = 0 or x = L when the distance travelled along the direction of
  // travel, s(tau) = v0 tau + a_dir tau^2 / 2, equals dir (boundary - x0).
  const double ad = dir_ * acc_;  // acceleration along the direction of travel
  for (const double boundary : {0.0, L_}) {
    const double target = dir_ * (boundary - x0_);
    if (std::abs(ad) < 1e-300) {
      if (v0_ > 0 && target > 0) add(t_entry_ + target / v0_);
      continue;
    }
    const double disc = v0_ * v0_ + 2.0 * ad * target;
    if (disc < 0) continue;
    const double sq = std::sqrt(disc);
    // Stable quadratic roots of ad/2 tau^2 + v0 tau - target = 0.
    const double q = -0.5 * (v0_ + std::copysign(sq, v0_ == 0.0 ? 1.0 : v0_));
    const double r1 = q / (0.5 * ad);
    const double r2 = (q != 0.0) ? -target / q : r1;
    for (double r : {r1, r2})
      if (r > 0) add(t_entry_ + r);
  }
  std::sort(ev.begin(), ev.end());
  ev.erase(std::unique(ev.begin(), ev.end()), ev.end());
  return ev;
}

}  // namespace traverse::beam
