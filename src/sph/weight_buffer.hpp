#pragma once
// The viscous weights' storage (SphSolver::Impl::pair_w): doubles in one block that grows with
// realloc, which keeps the content without a second copy live next to it (glibc moves a large
// block's pages with mremap), where a std::vector's growth holds the old and the new array at
// once: in the laboratory impact that pair was the heap's peak (docs/performance.md, session 23:
// SPH, "Memory"). The content beyond what a caller wrote is indeterminate.

#include <cstddef>
#include <cstdlib>
#include <new>
#include <span>

namespace shatter::sph {

class WeightBuffer {
 public:
  WeightBuffer() = default;
  WeightBuffer(const WeightBuffer&) = delete;
  WeightBuffer& operator=(const WeightBuffer&) = delete;
  ~WeightBuffer() { std::free(data_); }

  double* data() { return data_; }
  const double* data() const { return data_; }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return size_; }
  bool empty() const { return size_ == 0; }
  double operator[](std::size_t i) const { return data_[i]; }
  operator std::span<double>() { return {data_, size_}; }

  // At least n doubles, the first size() kept.
  void grow(std::size_t n) {
    if (n <= size_) return;
    void* p = std::realloc(data_, n * sizeof(double));
    if (p == nullptr) throw std::bad_alloc();
    data_ = static_cast<double*>(p);
    size_ = n;
  }
  // At least n doubles, the content dropped (no copy).
  void grow_discarding(std::size_t n) {
    if (n <= size_) return;
    std::free(data_);
    data_ = nullptr;
    size_ = 0;
    grow(n);
  }

 private:
  double* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace shatter::sph
