// Length units the two documents use. Exact by definition (international foot and inch).
#pragma once

namespace rangekit::units {

inline constexpr double metres_per_foot = 0.3048;
inline constexpr double metres_per_inch = 0.0254;

constexpr double feet_to_metres(double feet) { return feet * metres_per_foot; }
constexpr double metres_to_feet(double metres) { return metres / metres_per_foot; }
constexpr double inches_to_metres(double inches) { return inches * metres_per_inch; }
constexpr double metres_to_inches(double metres) { return metres / metres_per_inch; }

// Speed of light in vacuum, for time-of-flight physics (m/s).
inline constexpr double speed_of_light = 299'792'458.0;

}  // namespace rangekit::units
