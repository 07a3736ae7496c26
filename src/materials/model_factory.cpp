#include "materials/model_factory.hpp"

#include <stdexcept>

#include "materials/elastic_constants.hpp"

namespace shatter::materials {

namespace {
double opt(const MaterialSpec& s, const char* key, double fallback) {
  const auto it = s.params.find(key);
  return it == s.params.end() ? fallback : it->second;
}
}  // namespace

AnyEos make_eos(const MaterialSpec& s) {
  const double rho0 = s.get("rho0");
  if (s.eos == "tillotson") {
    return eos::Tillotson({rho0, s.get("A"), s.get("B"), s.get("a"), s.get("b"), s.get("E0"),
                           s.get("Eiv"), s.get("Ecv"), s.get("rho_iv"), s.get("alpha"),
                           s.get("beta")});
  }
  if (s.eos == "tillotson_simplified") {
    return eos::TillotsonSimplified({rho0, s.get("A"), s.get("a"), s.get("b")});
  }
  if (s.eos == "mie_gruneisen") {
    return eos::MieGruneisen({rho0, s.get("c0"), s.get("s"), s.get("gamma0")});
  }
  if (s.eos == "linear_polynomial") {
    eos::LinearPolynomialParams q;
    q.rho0 = rho0;
    const char* keys[7] = {"C0", "C1", "C2", "C3", "C4", "C5", "C6"};
    for (int k = 0; k < 7; ++k) q.C[k] = opt(s, keys[k], 0.0);
    return eos::LinearPolynomial(q);
  }
  if (s.eos == "linear_elastic") {
    const double k =
        s.params.count("bulk_modulus") ? s.get("bulk_modulus") : elastic_constants(s).K;
    return eos::LinearElastic({rho0, k});
  }
  if (s.eos == "ideal_gas") return eos::IdealGas({rho0, s.get("gamma")});
  throw MaterialError("material '" + s.name + "': unknown eos '" + s.eos + "'", "eos");
}

AnyStrength make_strength(const MaterialSpec& s) {
  const std::string& m = s.strength;
  if (m == "hydro") {
    strength::Hydro h;
    if (has_any_elastic_key(s)) {
      // Keeps E_Y for a damage model; the shear modulus stays 0 (no deviator, Eq. 13 bulk only).
      h.elastic.young = elastic_constants(s).young;
    }
    return h;
  }
  const auto el = elastic_constants(s);
  if (m == "elastic") return strength::Elastic{el};
  if (m == "von_mises") return strength::J2Plasticity{el, s.get("yield"), 0.0};
  if (m == "linear_hardening") {
    return strength::J2Plasticity{el, s.get("yield"), s.get("plastic_modulus")};
  }
  if (m == "benz_asphaug") return strength::BenzAsphaug{el, s.get("yield")};
  if (m == "drucker_prager") {
    return strength::DruckerPrager{el, s.get("cohesion"), s.get("friction"), s.get("dilatancy"),
                                   s.get("tension_cutoff")};
  }
  if (m == "lundborg" || m == "modified_lundborg") {
    // The pressure-dependent surface both share (Eq. 4); in the order the aggregate lists them.
    const double cohesion = s.get("cohesion");
    const double friction_intact = s.get("friction_intact");
    const double friction_damaged = s.get("friction_damaged");
    const double limit = s.get("strength_limit");
    // The tension cut-off: absent, the models' default (-infinity, no cut-off).
    const bool cutoff = s.params.count("tension_cutoff") != 0;
    if (m == "lundborg") {
      strength::Lundborg l{
          el, cohesion, friction_intact, friction_damaged, limit, opt(s, "melt_energy", 0.0)};
      if (cutoff) l.tension_cutoff = s.get("tension_cutoff");
      return l;
    }
    strength::ModifiedLundborg l{
        el,    cohesion,           friction_intact,         friction_damaged,
        limit, s.get("dilatancy"), opt(s, "melt_heat", 0.0)};
    if (cutoff) l.tension_cutoff = s.get("tension_cutoff");
    return l;
  }
  throw MaterialError("material '" + s.name + "': unknown strength '" + m + "'", "strength");
}

}  // namespace shatter::materials
