#include "rangekit/sim/motion.hpp"

#include <cmath>

namespace rangekit {

Result<Motion> Motion::path(std::vector<PathPoint> points, bool repeat) {
  if (points.empty()) return make_error(Errc::out_of_range, "a path needs at least one point");
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].time_s) || !std::isfinite(points[i].position)) {
      return make_error(Errc::bad_number, "path point " + std::to_string(i + 1) + " is not a finite number");
    }
    if (i > 0 && points[i].time_s <= points[i - 1].time_s) {
      return make_error(Errc::out_of_range, "path point " + std::to_string(i + 1) + ": times must increase");
    }
  }
  const double start = points.front().position;  // read before the vector is moved from
  return Motion(start, 0.0, std::move(points), repeat);
}

double Motion::position_at(Nanos time) const {
  double t = static_cast<double>(time.count()) / 1e9;
  if (points_.empty()) return start_ + speed_ * t;
  if (points_.size() == 1) return points_.front().position;
  const double first = points_.front().time_s;
  const double last = points_.back().time_s;
  if (repeat_ && t > last) t = first + std::fmod(t - first, last - first);
  if (t <= first) return points_.front().position;
  if (t >= last) return points_.back().position;
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (t <= points_[i].time_s) {
      const auto& a = points_[i - 1];
      const auto& b = points_[i];
      return a.position + (b.position - a.position) * (t - a.time_s) / (b.time_s - a.time_s);
    }
  }
  return points_.back().position;
}

}  // namespace rangekit
