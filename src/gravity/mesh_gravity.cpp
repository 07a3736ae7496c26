// The particle-mesh gravity solve (Hockney & Eastwood 1988, Sec. 6-5): cloud-in-cell deposit,
// the isolated potential by one FFT convolution on the doubled mesh, the centred-difference
// acceleration, cloud-in-cell interpolation back (see mesh_gravity.hpp).

#include "shatter/gravity/mesh_gravity.hpp"

#include <fftw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gravity/cic.hpp"

namespace shatter::gravity {
namespace {

// The potential of a unit mass spread over one cell at its own node, in units of 1/h: the mean
// of 1/|r| over a unit cube about its centre, 2.38008 (H&E Sec. 6-5-4 replace the singular
// G(0) by a finite value; the cube average keeps the self-energy of a cell-filling mass right).
constexpr double kSelfGreen = 2.380077;

// FFTW buffers, freed with fftw_free.
struct FftwDeleter {
  void operator()(void* p) const { fftw_free(p); }
};
template <class T>
using FftwBuffer = std::unique_ptr<T[], FftwDeleter>;

}  // namespace

struct MeshGravity::Impl {
  int n = 0;   // active nodes per side
  int np = 0;  // padded nodes per side, 2n
  std::size_t real_size = 0, complex_size = 0;
  FftwBuffer<double> rho;                   // padded mesh: mass, then potential
  FftwBuffer<fftw_complex> spectrum;        // its transform
  std::vector<std::complex<double>> green;  // transform of 1/|r| (unit spacing), / np^3
  std::vector<double> ax, ay, az;           // mesh acceleration on the active n^3 nodes
  fftw_plan forward = nullptr, backward = nullptr;

  explicit Impl(int cells);
  ~Impl() {
    fftw_destroy_plan(forward);
    fftw_destroy_plan(backward);
  }
  std::size_t at(int i, int j, int k) const {  // padded mesh, row-major
    return (std::size_t(i) * std::size_t(np) + std::size_t(j)) * std::size_t(np) + std::size_t(k);
  }
  std::size_t active(int i, int j, int k) const {
    return (std::size_t(i) * std::size_t(n) + std::size_t(j)) * std::size_t(n) + std::size_t(k);
  }
  void make_green();
  void convolve();
  void differentiate(double G, double h);
};

MeshGravity::Impl::Impl(int cells) : n(cells), np(2 * cells) {
  real_size = std::size_t(np) * std::size_t(np) * std::size_t(np);
  complex_size = std::size_t(np) * std::size_t(np) * std::size_t(np / 2 + 1);
  rho.reset(fftw_alloc_real(real_size));
  spectrum.reset(fftw_alloc_complex(complex_size));
  if (!rho || !spectrum) throw std::bad_alloc();
  // Plans are made once (FFTW's planner is not thread-safe); ESTIMATE does not time candidate
  // plans, so the plan, and with it every bit of the result, is the same on every run.
  forward = fftw_plan_dft_r2c_3d(np, np, np, rho.get(), spectrum.get(), FFTW_ESTIMATE);
  backward = fftw_plan_dft_c2r_3d(np, np, np, spectrum.get(), rho.get(), FFTW_ESTIMATE);
  make_green();
  const std::size_t active_size = std::size_t(n) * std::size_t(n) * std::size_t(n);
  ax.assign(active_size, 0.0);
  ay.assign(active_size, 0.0);
  az.assign(active_size, 0.0);
}

// The isolated Green's function on the doubled mesh (H&E Eq. 6-71): g(i,j,k) = 1/|r| with the
// distance taken the short way round the period 2n, so the circular convolution equals the
// aperiodic one on the n^3 active nodes; transformed once, scaled by 1/np^3 for FFTW's
// unnormalised inverse.
void MeshGravity::Impl::make_green() {
  auto wrap = [&](int i) { return double(std::min(i, np - i)); };
  for (int i = 0; i < np; ++i) {
    for (int j = 0; j < np; ++j) {
      for (int k = 0; k < np; ++k) {
        const double r = std::hypot(wrap(i), wrap(j), wrap(k));
        rho[at(i, j, k)] = r > 0.0 ? 1.0 / r : kSelfGreen;
      }
    }
  }
  fftw_execute(forward);
  const double scale = 1.0 / double(real_size);
  green.resize(complex_size);
  for (std::size_t c = 0; c < complex_size; ++c) {
    green[c] = std::complex<double>(spectrum[c][0], spectrum[c][1]) * scale;
  }
}

// rho <- g * rho (circular convolution on the padded mesh): sum_j m_j / |r_i - r_j| in units of
// 1/h at every active node.
void MeshGravity::Impl::convolve() {
  fftw_execute(forward);
  for (std::size_t c = 0; c < complex_size; ++c) {
    const std::complex<double> v = std::complex<double>(spectrum[c][0], spectrum[c][1]) * green[c];
    spectrum[c][0] = v.real();
    spectrum[c][1] = v.imag();
  }
  fftw_execute(backward);
}

// rho holds the convolution; phi = -G/h conv (the potential), a = -grad phi by the centred
// difference (H&E Eq. 5-41) on the nodes 1..n-2 (the masses reach nodes 1..n-2 only).
void MeshGravity::Impl::differentiate(double G, double h) {
  const double c = G / (h * h) * 0.5;  // -d(phi)/dx = (G/h) (conv[i+1] - conv[i-1]) / (2h)
  tbb::parallel_for(1, n - 1, [&](int i) {
    for (int j = 1; j < n - 1; ++j) {
      for (int k = 1; k < n - 1; ++k) {
        const std::size_t a = active(i, j, k);
        ax[a] = c * (rho[at(i + 1, j, k)] - rho[at(i - 1, j, k)]);
        ay[a] = c * (rho[at(i, j + 1, k)] - rho[at(i, j - 1, k)]);
        az[a] = c * (rho[at(i, j, k + 1)] - rho[at(i, j, k - 1)]);
      }
    }
  });
}

MeshGravity::MeshGravity(int cells) {
  if (cells < kMinCells || cells > kMaxCells) {
    throw std::invalid_argument("MeshGravity: cells = " + std::to_string(cells) + " is outside [" +
                                std::to_string(kMinCells) + ", " + std::to_string(kMaxCells) + "]");
  }
  impl_ = std::make_unique<Impl>(cells);
}

MeshGravity::~MeshGravity() = default;

int MeshGravity::cells() const {
  return impl_->n;
}

SolveInfo MeshGravity::solve(const MassPoints& pts, double G, const FieldOut& out) {
  Impl& M = *impl_;
  SolveInfo info;
  const MeshFrame frame = fit_frame(pts, M.n);
  info.cell = frame.h;
  std::fill(M.rho.get(), M.rho.get() + M.real_size, 0.0);
  deposit(pts, frame, [&](int i, int j, int k) -> double& { return M.rho[M.at(i, j, k)]; });
  M.convolve();
  M.differentiate(G, frame.h);
  const auto conv = [&](int i, int j, int k) { return M.rho[M.at(i, j, k)]; };
  const auto acc = [&](int d, int i, int j, int k) {
    const std::size_t a = M.active(i, j, k);
    return d == 0 ? M.ax[a] : d == 1 ? M.ay[a] : M.az[a];
  };
  // Interpolation: each point writes its own entries, in parallel (no reduction).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pts.n, 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        interpolate_point(pts, frame, p, G, conv, acc, kSelfGreen, out);
                      }
                    });
  // The energy and the largest acceleration in particle order (serial: the same bits always).
  std::vector<double> phi_tmp;
  const double* phi = out.phi;
  if (phi == nullptr) {
    phi_tmp.resize(pts.n);
    FieldOut only_phi{nullptr, nullptr, nullptr, phi_tmp.data()};
    tbb::parallel_for(std::size_t{0}, pts.n, [&](std::size_t p) {
      interpolate_point(pts, frame, p, G, conv, acc, kSelfGreen, only_phi);
    });
    phi = phi_tmp.data();
  }
  double w = 0.0, a2 = 0.0;
  for (std::size_t p = 0; p < pts.n; ++p) {
    w += 0.5 * pts.m[p] * phi[p];
    if (out.ax)
      a2 = std::max(a2, out.ax[p] * out.ax[p] + out.ay[p] * out.ay[p] + out.az[p] * out.az[p]);
  }
  info.energy = w;
  info.a_max = std::sqrt(a2);
  return info;
}

double gravity_time_step(double a_max, double length, double factor) {
  if (!(a_max > 0.0)) return std::numeric_limits<double>::infinity();
  return factor * std::sqrt(length / a_max);
}

}  // namespace shatter::gravity
