// `shatter material`: the material probe (probe.hpp) on the command line, so that a user can check
// a catalogue entry (or an override of it) without running a simulation: EOS states at (rho, E),
// the principal Hugoniot, and the catalogue listing with sources.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "shatter/material/catalogue.hpp"
#include "shatter/material/catalogue_path.hpp"
#include "shatter/material/probe.hpp"

namespace shatter::cli {

namespace {

// A command-line value the user must fix; reported with exit code kBadInput.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Strict: the whole token must be one finite number ("3e9x", "1,5" or "nan" are refused rather
// than read as a prefix, which would silently probe another state).
double parse_number(std::string_view token, std::string_view option) {
  const std::string_view t = trim(token);
  double v = 0.0;
  const char* end = t.data() + t.size();
  const auto [ptr, ec] = std::from_chars(t.data(), end, v);
  if (t.empty() || ec != std::errc() || ptr != end || !std::isfinite(v)) {
    throw BadInput(fmt::format("{}: '{}' is not a finite number", option, token));
  }
  return v;
}

std::vector<double> parse_list(const std::string& text, std::string_view option) {
  std::vector<double> out;
  std::string_view rest = text;
  for (;;) {
    const auto comma = rest.find(',');
    out.push_back(parse_number(rest.substr(0, comma), option));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return out;
}

// MIN:MAX:N, N evenly spaced values including both ends.
std::vector<double> parse_sweep(const std::string& text, std::string_view option) {
  const auto c1 = text.find(':');
  const auto c2 = c1 == std::string::npos ? std::string::npos : text.find(':', c1 + 1);
  if (c2 == std::string::npos || text.find(':', c2 + 1) != std::string::npos) {
    throw BadInput(fmt::format("{}: '{}' must be MIN:MAX:N", option, text));
  }
  const double lo = parse_number(std::string_view(text).substr(0, c1), option);
  const double hi = parse_number(std::string_view(text).substr(c1 + 1, c2 - c1 - 1), option);
  const double nd = parse_number(std::string_view(text).substr(c2 + 1), option);
  if (!(nd >= 1.0 && nd <= 1e6 && nd == std::floor(nd))) {
    throw BadInput(fmt::format("{}: N = {} must be a whole number from 1 to 1e6", option, nd));
  }
  const int n = static_cast<int>(nd);
  std::vector<double> out(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    out[static_cast<std::size_t>(k)] = n == 1 ? lo : lo + (hi - lo) * k / (n - 1);
  }
  return out;
}

// Edit distance of `typed` against the best prefix of `name` (trailing characters of the name
// are free), case-insensitive: "basal" and "aluminium" are 0 from "basalt" and
// "aluminium_6061", "aluminum" is 1. Used only to suggest a name, never to pick one.
std::size_t prefix_distance(std::string_view typed, std::string_view name) {
  const auto lower = [](char c) { return std::tolower(static_cast<unsigned char>(c)); };
  std::vector<std::size_t> row(name.size() + 1), next(name.size() + 1);
  for (std::size_t j = 0; j <= name.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= typed.size(); ++i) {
    next[0] = i;
    for (std::size_t j = 1; j <= name.size(); ++j) {
      const std::size_t sub = row[j - 1] + (lower(typed[i - 1]) == lower(name[j - 1]) ? 0 : 1);
      next[j] = std::min({sub, row[j] + 1, next[j - 1] + 1});
    }
    std::swap(row, next);
  }
  return *std::min_element(row.begin(), row.end());
}

std::optional<std::string> nearest_name(std::string_view typed,
                                        const std::vector<std::string>& names) {
  std::optional<std::string> best;
  std::size_t best_d = 0, best_len = 0;
  for (const auto& n : names) {
    const std::size_t d = prefix_distance(typed, n);
    // Ties go to the shorter name: "basal" suggests "basalt", not "basalt_asteroid".
    if (!best || d < best_d || (d == best_d && n.size() < best_len)) {
      best = n;
      best_d = d;
      best_len = n.size();
    }
  }
  // More than a third of the typed characters wrong is no longer a typo.
  if (!best || best_d > std::max<std::size_t>(1, typed.size() / 3)) return std::nullopt;
  return best;
}

MaterialSpec find_material(const MaterialCatalogue& cat, const std::string& name) {
  if (cat.contains(name)) return cat.get(name);
  const auto names = cat.names();
  const auto hint = nearest_name(name, names);
  throw BadInput(fmt::format("unknown material '{}'{} (known: {}; see `shatter material --list`)",
                             name, hint ? fmt::format("; did you mean '{}'?", *hint) : "",
                             fmt::join(names, ", ")));
}

void apply_overrides(MaterialSpec& spec, const std::vector<std::string>& params) {
  for (const auto& kv : params) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw BadInput(fmt::format("--param '{}' must be KEY=VALUE (e.g. yield=30e6)", kv));
    }
    const std::string key(trim(std::string_view(kv).substr(0, eq)));
    spec.params[key] = parse_number(std::string_view(kv).substr(eq + 1), "--param " + key);
  }
  if (!params.empty()) spec.source += " [overridden on the command line]";
  validate(spec);  // unknown keys and non-physical values are refused here (MaterialError)
}

std::string csv_field(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void write_list(std::ostream& out, const MaterialCatalogue& cat, bool csv) {
  if (csv) {
    out << "name,eos,strength,source\n";
    for (const auto& n : cat.names()) {
      const auto& s = cat.get(n);
      fmt::print(out, "{},{},{},{}\n", n, s.eos, s.strength, csv_field(s.source));
    }
    return;
  }
  std::size_t w = 4;
  for (const auto& n : cat.names()) w = std::max(w, n.size());
  fmt::print(out, "{:<{}}  {:<20}  {:<17}  {}\n", "name", w, "eos", "strength", "source");
  for (const auto& n : cat.names()) {
    const auto& s = cat.get(n);
    fmt::print(out, "{:<{}}  {:<20}  {:<17}  {}\n", n, w, s.eos, s.strength, s.source);
  }
}

void write_summary(std::ostream& out, const MaterialSpec& spec) {
  fmt::print(out, "# {}: eos {}, strength {}{}\n# source: {}\n", spec.name, spec.eos, spec.strength,
             spec.porosity.empty() ? "" : ", porosity " + spec.porosity, spec.source);
}

void write_parameters(std::ostream& out, const MaterialSpec& spec) {
  out << "# parameters (SI):";
  for (const auto& [k, v] : spec.params) fmt::print(out, " {}={:g}", k, v);
  out << "\n";
}

// States: every rho with every E; rho defaults to rho0 and E to 0 (the reference state).
void parse_states(const MaterialOptions& o, const MaterialSpec& spec, std::vector<double>& rho,
                  std::vector<double>& energy) {
  if (!o.rho.empty()) rho = parse_list(o.rho, "--rho");
  if (!o.rho_sweep.empty()) {
    const auto s = parse_sweep(o.rho_sweep, "--rho-sweep");
    rho.insert(rho.end(), s.begin(), s.end());
  }
  if (!o.energy.empty()) energy = parse_list(o.energy, "--energy");
  if (!o.energy_sweep.empty()) {
    const auto s = parse_sweep(o.energy_sweep, "--energy-sweep");
    energy.insert(energy.end(), s.begin(), s.end());
  }
  for (double r : rho) {
    if (!(r > 0.0)) throw BadInput(fmt::format("density {} kg/m^3 must be > 0", r));
  }
  if (rho.empty()) rho.push_back(spec.get("rho0"));
  if (energy.empty()) energy.push_back(0.0);
  // Every rho with every E: two 1e6-point sweeps would print 1e12 rows (hours).
  constexpr double kMaxRows = 1e7;
  if (static_cast<double>(rho.size()) * static_cast<double>(energy.size()) > kMaxRows) {
    throw BadInput(fmt::format("{} densities x {} energies is more than {:.0e} states", rho.size(),
                               energy.size(), kMaxRows));
  }
}

// Hugoniot particle speeds: an explicit list, or n evenly spaced up to up_max; and the reference.
std::vector<double> parse_hugoniot(const MaterialOptions& o, HugoniotReference& ref) {
  std::vector<double> up;
  if (!o.up.empty()) up = parse_list(o.up, "--up");
  if (o.up_max) {
    if (!(*o.up_max > 0.0 && std::isfinite(*o.up_max))) {
      throw BadInput(fmt::format("--hugoniot {} m/s must be > 0", *o.up_max));
    }
    if (o.points < 2 || o.points > 1000000) {
      throw BadInput(fmt::format("--points {} must be from 2 to 1e6", o.points));
    }
    for (int k = 0; k < o.points; ++k) up.push_back(*o.up_max * k / (o.points - 1));
  }
  for (double u : up) {
    if (!(u >= 0.0)) throw BadInput(fmt::format("particle speed {} m/s must be >= 0", u));
  }
  if (o.ref_rho) {
    if (!(*o.ref_rho > 0.0)) {
      throw BadInput(fmt::format("--ref-rho {} kg/m^3 must be > 0", *o.ref_rho));
    }
    ref.rho = *o.ref_rho;
  }
  if (o.ref_energy) {
    if (!std::isfinite(*o.ref_energy)) {
      throw BadInput(fmt::format("--ref-energy {} J/kg must be finite", *o.ref_energy));
    }
    ref.energy = *o.ref_energy;
  }
  return up;
}

void write_states(std::ostream& out, const MaterialSpec& spec, const std::vector<double>& rho,
                  const std::vector<double>& energy, bool csv, bool states_wanted) {
  std::vector<EosSample> samples;
  samples.reserve(rho.size() * energy.size());
  for (double r : rho) {
    for (double e : energy) samples.push_back(probe_eos(spec, r, e));
  }
  if (csv) {
    write_eos_csv(out, samples);
    return;
  }
  if (!states_wanted) write_parameters(out, spec);
  out << "\n";
  if (!spec.porosity.empty()) out << "# matrix (solid) EOS states\n";
  write_eos_table(out, samples);
  if (!states_wanted && !spec.porosity.empty()) {
    // The crush curve of the compaction model (kernels/porosity/crush.hpp).
    fmt::print(out, "\n# crush curve ({}): distension alpha = rho_s / rho, cold bulk pressure\n",
               spec.porosity);
    write_crush_table(out, crush_curve(spec, 21));
  }
}

// A porous material's Hugoniot from rest is the porous one (probe.hpp), unless a reference
// state is given: then the matrix EOS's from that state.
void write_hugoniot(std::ostream& out, const MaterialSpec& spec, const std::vector<double>& up,
                    const HugoniotReference& ref, bool csv) {
  const bool porous = !spec.porosity.empty() && ref.rho <= 0.0 && ref.energy == 0.0;
  std::vector<HugoniotRow> rows;
  try {
    rows = porous ? porous_hugoniot(spec, up) : hugoniot(spec, up, ref);
  } catch (const std::runtime_error& e) {
    throw BadInput(e.what());  // no shocked state for some up: the request exceeds the EOS
  }
  if (csv) {
    write_hugoniot_csv(out, rows);
    return;
  }
  if (porous) {
    fmt::print(out, "\n# porous Hugoniot ({}) from rho = {:g} kg/m^3, E = 0 J/kg\n", spec.porosity,
               spec.get("rho0") / spec.get("alpha0"));
  } else {
    fmt::print(out, "\n# principal Hugoniot from rho = {:g} kg/m^3, E = {:g} J/kg\n",
               ref.rho > 0.0 ? ref.rho : spec.get("rho0"), ref.energy);
  }
  write_hugoniot_table(out, rows);
}

int run_material(const MaterialOptions& o, std::ostream& out) {
  const MaterialCatalogue cat =
      o.catalogue ? MaterialCatalogue::load(*o.catalogue) : MaterialCatalogue::builtin();
  if (o.list) {
    // Which file: an installed shatter finds its own (builtin_catalogue_path).
    spdlog::info("catalogue {}", (o.catalogue ? *o.catalogue : builtin_catalogue_path()).string());
    write_list(out, cat, o.csv);
    return kOk;
  }
  if (o.name.empty()) throw BadInput("name a material (or --list to see the catalogue)");
  MaterialSpec spec = find_material(cat, o.name);
  apply_overrides(spec, o.params);

  const bool hugoniot_wanted = o.up_max.has_value() || !o.up.empty();
  const bool states_wanted =
      !o.rho.empty() || !o.rho_sweep.empty() || !o.energy.empty() || !o.energy_sweep.empty();
  if (o.csv && hugoniot_wanted && states_wanted) {
    throw BadInput(
        "--csv writes one table: ask for states (--rho/--energy) or the Hugoniot "
        "(--hugoniot/--up), not both");
  }
  std::vector<double> rho, energy;
  parse_states(o, spec, rho, energy);
  HugoniotReference ref;
  const std::vector<double> up = parse_hugoniot(o, ref);

  if (!o.csv) write_summary(out, spec);
  if (states_wanted || !hugoniot_wanted) {
    write_states(out, spec, rho, energy, o.csv, states_wanted);
  }
  if (hugoniot_wanted) write_hugoniot(out, spec, up, ref, o.csv);
  if (!hugoniot_wanted && !states_wanted && !o.csv && !spec.porosity.empty()) {
    // A porous material's summary shows its porous Hugoniot from rest too (issue 29): the shock
    // states a user compares with the crush curve above, at lab-to-asteroid particle speeds.
    const std::vector<double> ups = {100.0, 300.0, 1000.0, 3000.0};
    write_hugoniot(out, spec, ups, ref, false);
  }
  return kOk;
}

}  // namespace

int material_command(const MaterialOptions& o) {
  std::ofstream file;
  if (o.out) {
    file.open(*o.out);
    if (!file) {
      spdlog::error("cannot write {}", o.out->string());
      return kFailure;
    }
  }
  std::ostream& out = o.out ? static_cast<std::ostream&>(file) : std::cout;
  try {
    if (const int rc = run_material(o, out); rc != kOk) return rc;
  } catch (const BadInput& e) {
    spdlog::error("{}", e.what());
    return kBadInput;
  } catch (const std::invalid_argument& e) {
    // MaterialError (a bad --param) and catalogue file errors (file:line: key ...).
    spdlog::error("{}", e.what());
    return kBadInput;
  }
  out.flush();
  if (!out) {
    spdlog::error("writing the output failed");
    return kFailure;
  }
  return kOk;
}

}  // namespace shatter::cli
