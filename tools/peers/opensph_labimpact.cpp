// Command-line driver that runs OpenSPH (github.com/pavelsevecek/OpenSPH) on the particles written
// by tools/peers/opensph_input.py, for the SPH peer comparison of docs/performance.md ("Peers
// (session 22)"). It is not part of shatter's build: it compiles against OpenSPH's core library
// (build: tools/peers/opensph/CMakeLists.txt). It prints the step count, the loop's CPU and
// wall time and the energies.
//
// Usage: osph-labimpact INPUT.osph [--threads N] [--integrator leapfrog|pc]
//        [--criterion collision|all|courant]
//        [--courant C] [--report-every T]
#include "Sph.h"

#include <sys/resource.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

using namespace Sph;

namespace {

double cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec) + double(u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_stime.tv_usec);
}

double wall_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

struct Point {
  double x, y, z, vx, vy, vz, m, rho;
};

struct BodyInput {
  std::string name;
  std::map<std::string, double> params;
  std::vector<Point> points;
};

struct Input {
  std::map<std::string, double> run;
  std::vector<BodyInput> bodies;
};

Input read_input(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw std::runtime_error("cannot open " + path);
  }
  Input input;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "body") {
      BodyInput body;
      ss >> body.name;
      std::string k;
      double v;
      while (ss >> k >> v) {
        body.params[k] = v;
      }
      const std::size_t n = std::size_t(body.params.at("n"));
      body.points.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        Point& p = body.points[i];
        in >> p.x >> p.y >> p.z >> p.vx >> p.vy >> p.vz >> p.m >> p.rho;
      }
      std::getline(in, line);
      input.bodies.push_back(std::move(body));
    } else {
      double v;
      ss >> v;
      input.run[key] = v;
    }
  }
  return input;
}

// returns the given points (h in the fourth component); the domain is ignored
class GivenPoints : public IDistribution {
  Array<Vector> r;

 public:
  explicit GivenPoints(Array<Vector>&& r) : r(std::move(r)) {}

  Array<Vector> generate(IScheduler& UNUSED(scheduler), const Size n,
                         const IDomain& UNUSED(domain)) const override {
    if (n != r.size()) {
      throw std::runtime_error("point count mismatch");
    }
    return r.clone();
  }
};

struct Options {
  int threads = 2;
  std::string integrator = "leapfrog";
  std::string criterion = "collision";
  double courant = 0.2;
  double report_every = 1.e-6;
  int verbosity = 0;
};

class LabImpact : public IRun {
  Input input;
  Options options;

 public:
  double cpu_loop_start = 0., wall_loop_start = 0.;
  Size particles = 0;

  LabImpact(Input in, Options opt) : input(std::move(in)), options(opt) {}

  void setUp(SharedPtr<Storage> storage) override {
    settings.set(RunSettingsId::RUN_NAME, "shatter lab impact peer run"_s);
    settings.set(RunSettingsId::RUN_THREAD_CNT, options.threads);
    settings.set(RunSettingsId::RUN_END_TIME, Float(input.run.at("end_time")));
    settings.set(RunSettingsId::RUN_OUTPUT_TYPE, IoEnum::NONE);
    settings.set(RunSettingsId::RUN_LOGGER_VERBOSITY, options.verbosity);
    settings.set(RunSettingsId::SPH_AV_ALPHA, Float(input.run.at("av_alpha")));
    settings.set(RunSettingsId::SPH_AV_BETA, Float(input.run.at("av_beta")));
    settings.set(RunSettingsId::SPH_KERNEL, KernelEnum::CUBIC_SPLINE);
    settings.set(RunSettingsId::TIMESTEPPING_INITIAL_TIMESTEP, Float(input.run.at("dt_initial")));
    settings.set(RunSettingsId::TIMESTEPPING_MAX_TIMESTEP, Float(input.run.at("dt_max")));
    settings.set(RunSettingsId::TIMESTEPPING_COURANT_NUMBER, Float(options.courant));
    if (options.integrator == "leapfrog") {
      settings.set(RunSettingsId::TIMESTEPPING_INTEGRATOR, TimesteppingEnum::LEAP_FROG);
    } else {
      settings.set(RunSettingsId::TIMESTEPPING_INTEGRATOR, TimesteppingEnum::PREDICTOR_CORRECTOR);
    }
    // "collision": the criteria of OpenSPH's own collision presets (run/jobs/Presets.cpp,
    // makeAsteroidCollision and makeFragmentationAndReaccumulation); "all": the settings' default
    if (options.criterion == "collision") {
      settings.set(RunSettingsId::TIMESTEPPING_CRITERION,
                   TimeStepCriterionEnum::COURANT | TimeStepCriterionEnum::DIVERGENCE);
    } else if (options.criterion == "courant") {
      settings.set(RunSettingsId::TIMESTEPPING_CRITERION,
                   TimeStepCriterionEnum::COURANT | TimeStepCriterionEnum::ACCELERATION);
    }
    scheduler = Factory::getScheduler(settings);

    InitialConditions ic(settings);
    const Float h_factor = Float(input.run.at("h_factor"));
    for (const BodyInput& b : input.bodies) {
      const auto& p = b.params;
      BodySettings body;
      body.set(BodySettingsId::PARTICLE_COUNT, int(b.points.size()));
      body.set(BodySettingsId::EOS, EosEnum::TILLOTSON);
      body.set(BodySettingsId::DENSITY, Float(p.at("rho0")));
      body.set(BodySettingsId::BULK_MODULUS, Float(p.at("A")));
      body.set(BodySettingsId::TILLOTSON_NONLINEAR_B, Float(p.at("B")));
      body.set(BodySettingsId::TILLOTSON_SMALL_A, Float(p.at("a")));
      body.set(BodySettingsId::TILLOTSON_SMALL_B, Float(p.at("b")));
      body.set(BodySettingsId::TILLOTSON_ALPHA, Float(p.at("alpha")));
      body.set(BodySettingsId::TILLOTSON_BETA, Float(p.at("beta")));
      body.set(BodySettingsId::TILLOTSON_SUBLIMATION, Float(p.at("E0")));
      body.set(BodySettingsId::TILLOTSON_ENERGY_IV, Float(p.at("Eiv")));
      body.set(BodySettingsId::TILLOTSON_ENERGY_CV, Float(p.at("Ecv")));
      body.set(BodySettingsId::SHEAR_MODULUS, Float(p.at("shear")));
      body.set(BodySettingsId::RHEOLOGY_YIELDING, YieldingEnum::VON_MISES);
      body.set(BodySettingsId::ELASTICITY_LIMIT, Float(p.at("yield")));
      body.set(BodySettingsId::MELT_ENERGY, Float(p.at("melt")));
      if (p.at("damage") > 0.) {
        body.set(BodySettingsId::RHEOLOGY_DAMAGE, FractureEnum::SCALAR_GRADY_KIPP);
        body.set(BodySettingsId::WEIBULL_COEFFICIENT, Float(p.at("weibull_k")));
        body.set(BodySettingsId::WEIBULL_EXPONENT, Float(p.at("weibull_m")));
      } else {
        body.set(BodySettingsId::RHEOLOGY_DAMAGE, FractureEnum::NONE);
      }
      body.set(BodySettingsId::SMOOTHING_LENGTH_ETA, h_factor);
      body.set(BodySettingsId::ENERGY, 0._f);
      // the derivative criterion's scales of OpenSPH's MaterialProvider (run/jobs/MaterialJobs.cpp)
      body.set(BodySettingsId::STRESS_TENSOR_MIN, 4.e6_f);
      body.set(BodySettingsId::ENERGY_MIN, 10._f);
      body.set(BodySettingsId::DAMAGE_MIN, 0.25_f);

      Array<Vector> r;
      double mass = 0.;
      for (const Point& q : b.points) {
        // h = h_factor (m / rho)^(1/3): setQuantities multiplies the fourth component by eta
        r.push(Vector(q.x, q.y, q.z, std::cbrt(q.m / q.rho)));
        mass += q.m;
      }
      // a sphere of the body's volume: addMonolithicBody takes the total mass as volume * rho0
      const Float volume = mass / p.at("rho0");
      SphericalDomain domain(Vector(0._f), std::cbrt(3. * volume / (4. * PI)));
      GivenPoints distribution(std::move(r));
      AutoPtr<IMaterial> material = Factory::getMaterial(body);
      ic.addMonolithicBody(*storage, domain, std::move(material), distribution);
    }
    // exact masses and velocities, in the file's order (the bodies are appended in turn)
    ArrayView<Vector> r = storage->getValue<Vector>(QuantityId::POSITION);
    ArrayView<Vector> v = storage->getDt<Vector>(QuantityId::POSITION);
    ArrayView<Float> m = storage->getValue<Float>(QuantityId::MASS);
    Size i = 0;
    for (const BodyInput& b : input.bodies) {
      for (const Point& q : b.points) {
        if (std::abs(r[i][X] - q.x) > 1.e-12 || std::abs(r[i][Z] - q.z) > 1.e-12) {
          throw std::runtime_error("particle order changed by the storage");
        }
        m[i] = q.m;
        v[i] = Vector(q.vx, q.vy, q.vz);
        ++i;
      }
    }
    particles = storage->getParticleCnt();
    std::printf("opensph: %u particles in %zu bodies, %d threads, end time %g s\n",
                unsigned(particles), input.bodies.size(), options.threads,
                input.run.at("end_time"));
  }

  double end_time() const { return input.run.at("end_time"); }

  void tearDown(const Storage& UNUSED(storage), const Statistics& UNUSED(stats)) override {}
};

class Callbacks : public IRunCallbacks {
  LabImpact& run;
  double report_every;
  double next_report = 0.;

 public:
  Size steps = 0;
  double cpu_loop_start = 0., wall_loop_start = 0., cpu_loop_end = 0., wall_loop_end = 0.;

  Callbacks(LabImpact& run, double report_every) : run(run), report_every(report_every) {}

  void report(const Storage& storage, const double t, const double dt) {
    const Float ek = TotalKineticEnergy().evaluate(storage);
    const Float eu = TotalInternalEnergy().evaluate(storage);
    double failed = 0., total = 0.;
    if (storage.has(QuantityId::DAMAGE)) {
      ArrayView<const Float> D = storage.getValue<Float>(QuantityId::DAMAGE);
      ArrayView<const Float> m = storage.getValue<Float>(QuantityId::MASS);
      for (Size i = 0; i < D.size(); ++i) {
        total += m[i];
        // OpenSPH's DAMAGE column is D^(1/3)
        if (D[i] * D[i] * D[i] >= 0.9) {
          failed += m[i];
        }
      }
    }
    std::printf(
        "opensph: t = %.4g s step %u dt %.3g s kinetic %.6g J internal %.6g J total %.6g J "
        "failed(mass, D>=0.9 incl. projectile) %.4f\n",
        t, unsigned(steps), dt, ek, eu, ek + eu, total > 0. ? failed / total : 0.);
    std::fflush(stdout);
  }

  void onSetUp(const Storage& storage, Statistics& UNUSED(stats)) override {
    report(storage, 0., 0.);
    cpu_loop_start = cpu_seconds();
    wall_loop_start = wall_seconds();
    next_report = report_every;
  }

  void onTimeStep(const Storage& storage, Statistics& stats) override {
    ++steps;
    const double t = stats.get<Float>(StatisticsId::RUN_TIME);
    const double dt = stats.get<Float>(StatisticsId::TIMESTEP_VALUE);
    if (t + dt >= next_report) {
      // the loop's clock stops while the energies are summed
      const double c0 = cpu_seconds(), w0 = wall_seconds();
      report(storage, t + dt, dt);
      cpu_loop_start += cpu_seconds() - c0;
      wall_loop_start += wall_seconds() - w0;
      next_report += report_every;
    }
    cpu_loop_end = cpu_seconds();
    wall_loop_end = wall_seconds();
  }

  bool shouldAbortRun() const override { return false; }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s INPUT [--threads N] [--integrator leapfrog|pc] [--criterion "
                 "collision|all|courant] "
                 "[--courant C] [--report-every T]\n",
                 argv[0]);
    return 2;
  }
  Options opt;
  for (int a = 2; a + 1 < argc; a += 2) {
    const std::string k = argv[a];
    const std::string v = argv[a + 1];
    if (k == "--threads") {
      opt.threads = std::stoi(v);
    } else if (k == "--integrator") {
      opt.integrator = v;
    } else if (k == "--criterion") {
      opt.criterion = v;
    } else if (k == "--courant") {
      opt.courant = std::stod(v);
    } else if (k == "--verbosity") {
      opt.verbosity = std::stoi(v);
    } else if (k == "--report-every") {
      opt.report_every = std::stod(v);
    } else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  try {
    const double cpu0 = cpu_seconds(), wall0 = wall_seconds();
    LabImpact run(read_input(argv[1]), opt);
    Callbacks callbacks(run, opt.report_every);
    Storage storage;
    run.run(storage, callbacks);
    callbacks.report(storage, run.end_time(), 0.);
    const double loop_cpu = callbacks.cpu_loop_end - callbacks.cpu_loop_start;
    const double loop_wall = callbacks.wall_loop_end - callbacks.wall_loop_start;
    const double ps = double(run.particles) * double(callbacks.steps);
    std::printf(
        "opensph: done: %u steps, %u particles; loop %.3f s CPU, %.3f s wall: %.4g particle-steps "
        "per CPU-s, %.4g per wall-s; process so far %.3f s CPU, %.3f s wall\n",
        unsigned(callbacks.steps), unsigned(run.particles), loop_cpu, loop_wall, ps / loop_cpu,
        ps / loop_wall, cpu_seconds() - cpu0, wall_seconds() - wall0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "opensph: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
