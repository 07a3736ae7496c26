#pragma once
// The components a material point may carry (DESIGN.md, "Data"). Each is one aligned column in
// ParticleStore; a scene registers only those its systems and models ask for.

#include <array>
#include <cstdint>
#include <initializer_list>
#include <string_view>

namespace shatter {

// Real-valued (double) columns. Append new fields at the end of their section; the names in
// kFieldNames are what snapshots and checkpoints call them.
enum class Field : std::uint8_t {
  // kinematics
  x,
  y,
  z,
  vx,
  vy,
  vz,
  // mass and geometry
  mass,
  volume0,
  size0,
  rho,
  // thermodynamics and stress (Cauchy stress as seen by the momentum equation, Voigt order
  // xx, yy, zz, xy, yz, xz)
  energy,
  sxx,
  syy,
  szz,
  sxy,
  syz,
  sxz,
  pressure,
  soundspeed,
  // per-step increments written by the velocity-gradient stage (App. A.2 step 7): strain
  // increment (symmetric) and spin increment W = (L - L^T)/2 * dt (skew: xy, yz, xz parts)
  deps_xx,
  deps_yy,
  deps_zz,
  deps_xy,
  deps_yz,
  deps_xz,
  dspin_xy,
  dspin_yz,
  dspin_xz,
  // strength-model state
  sdev_xx,
  sdev_yy,
  sdev_zz,
  sdev_xy,
  sdev_yz,
  sdev_xz,  // undamaged deviator (damage on)
  plastic_strain,
  heat,
  // fracture state (MPM paper Sec. 3.3)
  damage,
  eps_min,
  eps_max,
  n_flaws,
  weibull_m,
  n_active,
  // affine velocity of APIC transfers (TransferKind::apic): C_p = grad v at the particle,
  // row-major (C_ij = dv_i / dx_j), carried from one step's G2P to the next step's P2G
  vgrad_xx,
  vgrad_xy,
  vgrad_xz,
  vgrad_yx,
  vgrad_yy,
  vgrad_yz,
  vgrad_zx,
  vgrad_zy,
  vgrad_zz,
  // tracer: the largest pressure a point has seen (Pa), kept by the constitutive update
  peak_pressure,
  // porous compaction state (issue 29): distension alpha = rho_s / rho, kept by the porosity
  // stage of the constitutive update (kernels/porosity)
  distension,
  // and the compaction work per unit mass the stage has booked, J/kg
  // (kernels/porosity/porosity.hpp, compaction_work): the part of the internal energy spent
  // closing pores. (The porosity 1 - 1/alpha is not stored: the outputs derive it,
  // shatter/io/columns.hpp, Derived::porosity.)
  compaction_heat,
  kCount
};

inline constexpr std::size_t kFieldCount = static_cast<std::size_t>(Field::kCount);

// A table, seven names a row, rather than one name a line.
// clang-format off
inline constexpr std::array<std::string_view, kFieldCount> kFieldNames = {
    "x",        "y",        "z",        "vx",       "vy",         "vz",        "mass",
    "volume0",  "size0",    "rho",      "energy",   "sxx",        "syy",       "szz",
    "sxy",      "syz",      "sxz",      "pressure", "soundspeed", "deps_xx",   "deps_yy",
    "deps_zz",  "deps_xy",  "deps_yz",  "deps_xz",  "dspin_xy",   "dspin_yz",  "dspin_xz",
    "sdev_xx",  "sdev_yy",  "sdev_zz",  "sdev_xy",  "sdev_yz",    "sdev_xz",   "plastic_strain",
    "heat",     "damage",   "eps_min",  "eps_max",  "n_flaws",    "weibull_m", "n_active",
    "vgrad_xx", "vgrad_xy", "vgrad_xz", "vgrad_yx", "vgrad_yy",   "vgrad_yz",  "vgrad_zx",
    "vgrad_zy", "vgrad_zz", "peak_pressure", "distension", "compaction_heat"};
// clang-format on

// Integer columns (64-bit so that particle ids never overflow).
enum class IField : std::uint8_t { id, body, fragment, kCount };
inline constexpr std::size_t kIFieldCount = static_cast<std::size_t>(IField::kCount);
inline constexpr std::array<std::string_view, kIFieldCount> kIFieldNames = {"id", "body",
                                                                            "fragment"};

constexpr std::string_view name_of(Field f) {
  return kFieldNames[static_cast<std::size_t>(f)];
}
constexpr std::string_view name_of(IField f) {
  return kIFieldNames[static_cast<std::size_t>(f)];
}

// A compile-time set of fields; used by stages to declare what they read and write, so that a
// stage cannot touch a column it did not ask for (checked by static_assert in Columns<>).
struct FieldSet {
  static_assert(kFieldCount <= 128, "FieldSet holds at most 128 fields");
  std::uint64_t lo = 0, hi = 0;

  constexpr FieldSet() = default;
  constexpr FieldSet(std::initializer_list<Field> fields) {
    for (Field f : fields) *this = with(f);
  }
  constexpr FieldSet with(Field f) const {
    FieldSet s = *this;
    const auto i = static_cast<unsigned>(f);
    if (i < 64)
      s.lo |= std::uint64_t{1} << i;
    else
      s.hi |= std::uint64_t{1} << (i - 64);
    return s;
  }
  constexpr bool has(Field f) const {
    const auto i = static_cast<unsigned>(f);
    return i < 64 ? ((lo >> i) & 1U) != 0 : ((hi >> (i - 64)) & 1U) != 0;
  }
  constexpr FieldSet operator|(FieldSet o) const {
    FieldSet s;
    s.lo = lo | o.lo;
    s.hi = hi | o.hi;
    return s;
  }
  constexpr bool operator==(const FieldSet&) const = default;
};

// Common groups of columns.
inline constexpr FieldSet kPosition{Field::x, Field::y, Field::z};
inline constexpr FieldSet kVelocity{Field::vx, Field::vy, Field::vz};
inline constexpr FieldSet kStress{Field::sxx, Field::syy, Field::szz,
                                  Field::sxy, Field::syz, Field::sxz};
inline constexpr FieldSet kStrainIncrement{Field::deps_xx, Field::deps_yy, Field::deps_zz,
                                           Field::deps_xy, Field::deps_yz, Field::deps_xz};
inline constexpr FieldSet kSpinIncrement{Field::dspin_xy, Field::dspin_yz, Field::dspin_xz};
inline constexpr FieldSet kVelocityGradient{Field::vgrad_xx, Field::vgrad_xy, Field::vgrad_xz,
                                            Field::vgrad_yx, Field::vgrad_yy, Field::vgrad_yz,
                                            Field::vgrad_zx, Field::vgrad_zy, Field::vgrad_zz};
inline constexpr FieldSet kDeviator{Field::sdev_xx, Field::sdev_yy, Field::sdev_zz,
                                    Field::sdev_xy, Field::sdev_yz, Field::sdev_xz};

}  // namespace shatter
