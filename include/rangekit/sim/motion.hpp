// Where a simulated target is over time: fixed, moving at a constant speed, or
// following a piecewise-linear path of (time, position) points (the emulators'
// scenes). Pure; the emulators evaluate it at their own clock's time.
#pragma once

#include <string>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/sim/clock.hpp"

namespace rangekit {

struct PathPoint {
  double time_s = 0;
  double position = 0;  // in the scene's unit (metres for the ULS, millimetres for the LS5)
};

class Motion {
 public:
  static Motion fixed(double position) { return Motion(position, 0.0, {}); }
  static Motion constant_speed(double start, double speed_per_s) { return Motion(start, speed_per_s, {}); }
  // Points must have strictly increasing times; before the first point the
  // target sits at the first position, after the last at the last one.
  static Result<Motion> path(std::vector<PathPoint> points, bool repeat);

  [[nodiscard]] double position_at(Nanos time) const;

 private:
  Motion(double start, double speed, std::vector<PathPoint> points, bool repeat = false)
      : start_(start), speed_(speed), points_(std::move(points)), repeat_(repeat) {}
  double start_;
  double speed_;
  std::vector<PathPoint> points_;
  bool repeat_;
};

}  // namespace rangekit
