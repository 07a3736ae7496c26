#pragma once
// Self-gravity of a set of point masses by the particle-mesh method with isolated boundaries
// (Hockney & Eastwood 1988, "Computer Simulation Using Particles", Sec. 6-5: the zero-padded
// ("doubled") mesh and the isolated Green's function). One solver for both methods: MPM hands it
// its grid nodes' masses, SPH its particles. Implemented in src/gravity/.
//
// The mesh is a cube of `cells` nodes per side laid over the masses' bounding box (re-fitted at
// every solve), padded to 2 x cells per side for the FFT convolution (FFTW3). Mass assignment and
// interpolation are both cloud-in-cell (H&E Eq. 5-40) and the mesh acceleration is the centred
// difference of the potential, so the pair forces are antisymmetric: the total force is zero to
// round-off (momentum conserved) and a particle exerts no force on itself (H&E Sec. 5-4).
//
// Determinism: the deposit is one serial loop in particle order, the FFTs are one serial FFTW
// plan, and the interpolation writes each particle's own value: the result has the same bits on
// any thread count.

#include <cstddef>
#include <memory>

namespace shatter::gravity {

// CODATA 2018, m^3 kg^-1 s^-2 (the pkdgrav hand-off uses the same value).
inline constexpr double kNewtonG = 6.67430e-11;

// Pointers to n masses and where their field goes; phi may be null.
struct MassPoints {
  std::size_t n = 0;
  const double* x = nullptr;
  const double* y = nullptr;
  const double* z = nullptr;
  const double* m = nullptr;
};
struct FieldOut {
  double* ax = nullptr;
  double* ay = nullptr;
  double* az = nullptr;
  double* phi = nullptr;  // potential at each point, J/kg, its own CIC self-term removed
};

// What one solve reports beside the field.
struct SolveInfo {
  double energy = 0.0;  // W = 1/2 sum_p m_p phi_p, self-energies removed, J
  double a_max = 0.0;   // max_p |a_p|, m/s^2
  double cell = 0.0;    // mesh spacing of this solve, m
};

class MeshGravity {
 public:
  static constexpr int kMinCells = 8;
  static constexpr int kMaxCells = 256;  // 512^3 padded mesh: 3 arrays of ~1 GiB at the limit

  // cells: mesh nodes per side over the masses' bounding box, in [kMinCells, kMaxCells].
  explicit MeshGravity(int cells);
  ~MeshGravity();
  MeshGravity(const MeshGravity&) = delete;
  MeshGravity& operator=(const MeshGravity&) = delete;

  // Potential and acceleration of the points' own mass, G the constant of gravitation.
  SolveInfo solve(const MassPoints& pts, double G, const FieldOut& out);
  int cells() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Gravity's limit on the time step: dt <= factor sqrt(length / a_max), the time to fall a
// fraction of `length` (a cell or smoothing length) from rest (the usual N-body criterion, e.g.
// Springel 2005, MNRAS 364, Eq. 34, with the softening replaced by the resolution length).
// Infinite when nothing accelerates.
double gravity_time_step(double a_max, double length, double factor);

}  // namespace shatter::gravity
