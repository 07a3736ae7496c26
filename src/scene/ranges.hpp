#pragma once
// Physically meaningful ranges of scene values, each with the reason for its bounds. Values
// outside are refused by name (Reader::within) rather than run: they would overflow (an impact
// speed whose 1/2 v^2 is infinite), exhaust memory (a spacing giving 1e30 points) or describe no
// impact this code models. The bounds are generous: impacts up to 1000 km/s, bodies from
// micrometres to larger than Jupiter, very weak regolith (material strengths have no lower bound
// but zero, src/materials/validate.cpp).

namespace shatter::scene::ranges {

// Speeds: 1000 km/s is ten times the fastest impacts in the solar system (long-period comets
// into the Sun, ~600 km/s at its surface; heliocentric asteroid impacts < 75 km/s) and 0.3 % of
// the speed of light: the Newtonian equations and the EOS models stop being meaningful long before.
inline constexpr double kMaxSpeed = 1.0e6;  // m/s
inline constexpr const char* kSpeedReason =
    "10x the fastest solar-system impacts and 0.3% of c; Newtonian mechanics and the EOS models "
    "are not meaningful beyond";
// Specific internal energy: twice the specific kinetic energy at kMaxSpeed (5e11 J/kg).
inline constexpr double kMaxSpecificEnergy = 1.0e12;  // J/kg
inline constexpr const char* kEnergyReason = "twice 1/2 v^2 at the largest impact speed, 1000 km/s";
// Lengths: a nanometre cell is below the continuum; 1e8 m is larger than Jupiter (7e7 m).
inline constexpr double kMinLength = 1.0e-9;  // m
inline constexpr double kMaxLength = 1.0e8;   // m
inline constexpr const char* kLengthReason =
    "from below the continuum scale to larger than Jupiter (radius 7e7 m)";
// Coordinates: 1e10 m (0.07 au) around the origin; with cells of a few metres beyond it a double
// cannot resolve a particle's displacement in one step.
inline constexpr double kMaxCoordinate = 1.0e10;  // m
inline constexpr const char* kCoordinateReason =
    "0.07 au; farther from the origin a double no longer resolves a step's displacement";
// Simulated time: 1e10 s (300 years) exceeds any impact or re-accumulation run.
inline constexpr double kMaxTime = 1.0e10;  // s
inline constexpr const char* kTimeReason = "300 years: longer than any impact simulation";
// Gravity: 1e6 m/s^2 is 3600 times the Sun's surface gravity (274 m/s^2).
inline constexpr double kMaxGravity = 1.0e6;  // m/s^2
inline constexpr const char* kGravityReason = "3600 times the surface gravity of the Sun";
// Points: about 0.5 kB each, so 1e9 points need ~500 GB.
inline constexpr double kMaxPoints = 1.0e9;
// Output files: a million snapshots or checkpoints of one run is a mistake in the cadence.
inline constexpr double kMaxOutputs = 1.0e6;

}  // namespace shatter::scene::ranges
