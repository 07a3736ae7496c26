#pragma once
// Material probe: look at an equation of state without running a simulation. Pressure, sound
// speed and Tillotson region at given (rho, E); the principal Hugoniot from the Rankine–Hugoniot
// jump conditions solved with the material's own EOS. Used by `shatter material ...` and by the
// verification tests (planar impact against the Hugoniot).

#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "shatter/material/catalogue.hpp"

namespace shatter {

struct EosSample {
  double rho = 0.0;         // kg/m^3
  double energy = 0.0;      // J/kg
  double pressure = 0.0;    // Pa (thermodynamic, from the EOS alone)
  double bulk_speed = 0.0;  // c_K, Eq. 12 (with the floor of docs/materials.md), m/s
  double soundspeed = 0.0;  // c_p, Eq. 13 with the strength model's shear modulus, m/s
  std::string region;       // Tillotson region (compressed, cold_expanded, mixed, hot_expanded,
                            // vapour_expansion), or the EOS name for other models
};

// Throws std::invalid_argument (MaterialError) for an invalid spec.
EosSample probe_eos(const MaterialSpec& spec, double rho, double energy);

// One state on the principal Hugoniot: a shock of particle speed up running at Us into the
// reference state (rho_ref, E_ref, p_ref = p(rho_ref, E_ref)) leaves (rho, E, p):
//   mass      rho_ref Us = rho (Us - up)
//   momentum  p - p_ref = rho_ref Us up
//   energy    E - E_ref = (p + p_ref) / 2 (1/rho_ref - 1/rho)
struct HugoniotRow {
  double up = 0.0;      // m/s
  double us = 0.0;      // m/s
  double p = 0.0;       // Pa
  double rho = 0.0;     // kg/m^3
  double energy = 0.0;  // J/kg
};

struct HugoniotReference {
  double rho = 0.0;     // kg/m^3; <= 0 means the material's rho0
  double energy = 0.0;  // J/kg
};

// Rows for each particle speed (>= 0). up = 0 gives the acoustic limit Us = c_K(reference).
// Throws std::runtime_error when no compressive root exists for some up (EOS too soft).
std::vector<HugoniotRow> hugoniot(const MaterialSpec& spec, std::span<const double> up,
                                  HugoniotReference ref = {});
// n evenly spaced particle speeds from 0 to up_max.
std::vector<HugoniotRow> hugoniot(const MaterialSpec& spec, double up_max, int n,
                                  HugoniotReference ref = {});

// Porous materials (MaterialSpec::porosity, issue 29; kernels/porosity). The crush curve: n
// points of distension alpha against volumetric strain eps_V = ln(rho00 / rho) (eps_alpha, from 0
// to 1.1 eps_c of W06 Eq. 10) or against bulk pressure (p_alpha, from 0 to 1.2 p_s), with the
// bulk density and the cold (E = 0) bulk pressure p_s(alpha rho, 0) / alpha of each point.
struct CrushRow {
  double eps_v = 0.0;     // volumetric strain from the initial bulk density (< 0 compressed)
  double pressure = 0.0;  // bulk pressure, Pa
  double alpha = 1.0;     // distension rho_s / rho
  double rho = 0.0;       // bulk density, kg/m^3
};
// Throws std::invalid_argument for a material without porosity; n >= 2.
std::vector<CrushRow> crush_curve(const MaterialSpec& spec, int n);
void write_crush_table(std::ostream& out, std::span<const CrushRow> rows);
void write_crush_csv(std::ostream& out, std::span<const CrushRow> rows);
// The porous Hugoniot from the material at rest (rho0 / alpha0, E = 0, p = 0): the jump
// conditions solved with the kernel's own porosity policy (compaction to the crush curve, then
// p = p_s(alpha rho, E) / alpha). Throws std::runtime_error where no root is bracketed.
std::vector<HugoniotRow> porous_hugoniot(const MaterialSpec& spec, std::span<const double> up);

// Writers: CSV with units in the header, and an aligned human-readable table.
void write_hugoniot_csv(std::ostream& out, std::span<const HugoniotRow> rows);
void write_hugoniot_table(std::ostream& out, std::span<const HugoniotRow> rows);
void write_eos_csv(std::ostream& out, std::span<const EosSample> samples);
void write_eos_table(std::ostream& out, std::span<const EosSample> samples);

}  // namespace shatter
