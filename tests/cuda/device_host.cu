// SPDX-License-Identifier: MIT
// The same rows evaluated on the device and on the host, from one source: the pair energy,
// its gradient, `value_gradient`, and the projected Hessians by `analytic` and `exact`, for
// vertex-face (signed length, quadratic penalty), edge-edge (unsigned length, log barrier) and
// closest-feature edge-edge pairs, in float and double. Exit 77 (ctest: skipped) with
// "skipped: no CUDA device" where there is none.
//
// Tolerance: the device compiler contracts a·b + c into one FMA where the host compiler
// (without -ffp-contract=fast) rounds twice, so the two sides round differently at many steps
// of each pair. The rows are well conditioned (random pairs, no near-parallel edges), so the
// differences stay at a few hundred ε of the row's largest entry; the bound is 10⁴ ε of it
// (2.2e-12 in double, 1.2e-3 in float), and statuses must agree exactly.
#include <pce/pce.hpp>

#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

namespace {

constexpr int kRows = 256;
constexpr int kWidth =
    1 + 1 + 12 + 1 + 12 + 144 + 144;  // status, value, gradient, vg value, vg gradient, analytic, exact
constexpr int kKinds = 3;

template <class S> PCE_HOST_DEVICE void put_row(S* o, pce::Status s, const S& value, const pce::Vec12<S>& g,
                                                pce::Status vs, const S& v, const pce::Vec12<S>& vg,
                                                const pce::Mat12<S>& a, const pce::Mat12<S>& e) {
  o[0] = S(int(s) + 10 * int(vs));
  o[1] = value;
  for (int i = 0; i < 12; ++i) o[2 + i] = g[i];
  o[14] = v;
  for (int i = 0; i < 12; ++i) o[15 + i] = vg[i];
  for (int i = 0; i < 144; ++i) o[27 + i] = a(i / 12, i % 12);
  for (int i = 0; i < 144; ++i) o[171 + i] = e(i / 12, i % 12);
}

// One plane-kind row: the pair energy, its gradient, both projections and `value_gradient`.
template <class Pair, class S, class Length, class Penalty>
PCE_HOST_DEVICE void plane_row(const pce::Vec12<S>& x, const Length& length, const Penalty& penalty, S* o) {
  pce::Vec12<S> g = pce::Vec12<S>::Zero(), vg = pce::Vec12<S>::Zero();
  pce::Mat12<S> a = pce::Mat12<S>::Zero(), e = pce::Mat12<S>::Zero();
  S value = 0, v = 0;
  pce::PairEnergy<S> pe;
  const pce::Status s = pce::pair_energy<Pair>(x, length, penalty, pe);
  if (s == pce::Status::ok) {
    value = pe.psi.value, g = pce::energy_gradient(pe);
    a = pce::projected_hessian<pce::Projection::analytic>(pe), e = pce::projected_hessian<pce::Projection::exact>(pe);
  }
  const pce::Status vs = pce::value_gradient<Pair>(x, length, penalty, v, vg);
  put_row(o, s, value, g, vs, v, vg, a, e);
}

// Row `i` of kind `kind` into `o` (kWidth scalars).
template <class S> PCE_HOST_DEVICE void row(int kind, const S* xs, S* o) {
  pce::Vec12<S> x;
  for (int i = 0; i < 12; ++i) x[i] = xs[i];
  if (kind == 0) return plane_row<pce::VertexFace>(x, pce::SignedLength{}, pce::QuadraticPenalty{2.0, 0.5}, o);
  if (kind == 1) return plane_row<pce::EdgeEdge>(x, pce::UnsignedLength{}, pce::LogBarrierPenalty{1.0, 2.0}, o);
  const pce::Vec12<S> zero = pce::Vec12<S>::Zero();
  pce::Vec12<S> g = zero;
  pce::Mat12<S> a = pce::Mat12<S>::Zero(), e = a;
  S value = 0;
  pce::ClosestFeatureEnergy<S> ce;
  const pce::Status s =
      pce::closest_feature_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 2.0}, ce);
  if (s == pce::Status::ok) {
    value = ce.psi.value, g = pce::energy_gradient(ce);
    a = pce::projected_hessian<pce::Projection::analytic>(ce), e = pce::projected_hessian<pce::Projection::exact>(ce);
  }
  put_row(o, s, value, g, pce::Status::ok, S(0), zero, a, e);
}

template <class S> __global__ void rows_kernel(const S* x, S* out, int n) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n * kKinds) row<S>(i / n, x + 12 * (i % n), out + std::size_t(i) * kWidth);
}

template <class S> int compare(const char* name) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<S> x(12 * kRows);
  for (auto& c : x) c = S(u(rng));
  const std::size_t n_out = std::size_t(kRows) * kKinds * kWidth;
  std::vector<S> host(n_out), dev(n_out);
  for (int i = 0; i < kRows * kKinds; ++i)
    row<S>(i / kRows, x.data() + 12 * (i % kRows), host.data() + std::size_t(i) * kWidth);
  S *dx = nullptr, *dout = nullptr;
  if (cudaMalloc(&dx, x.size() * sizeof(S)) != cudaSuccess || cudaMalloc(&dout, n_out * sizeof(S)) != cudaSuccess) {
    std::printf("FAIL %s: cudaMalloc\n", name);
    return 1;
  }
  cudaMemcpy(dx, x.data(), x.size() * sizeof(S), cudaMemcpyHostToDevice);
  rows_kernel<S><<<(kRows * kKinds + 127) / 128, 128>>>(dx, dout, kRows);
  const cudaError_t err = cudaDeviceSynchronize();
  cudaMemcpy(dev.data(), dout, n_out * sizeof(S), cudaMemcpyDeviceToHost);
  cudaFree(dx);
  cudaFree(dout);
  if (err != cudaSuccess) {
    std::printf("FAIL %s: kernel: %s\n", name, cudaGetErrorString(err));
    return 1;
  }
  const S tol = S(1e4) * std::numeric_limits<S>::epsilon();
  int bad = 0, ok_rows = 0;
  double worst = 0;
  for (int r = 0; r < kRows * kKinds; ++r) {
    const S* h = host.data() + std::size_t(r) * kWidth;
    const S* d = dev.data() + std::size_t(r) * kWidth;
    if (h[0] != d[0]) {
      if (bad++ < 5)
        std::printf("  %s row %d: status %g on the host, %g on the device\n", name, r, double(h[0]), double(d[0]));
      continue;
    }
    ok_rows += h[0] == S(0);
    S scale = 0;
    for (int j = 1; j < kWidth; ++j) scale = std::fmax(scale, std::fabs(h[j]));
    for (int j = 1; j < kWidth; ++j) {
      const double rel = double(std::fabs(h[j] - d[j])) / double(scale > 0 ? scale : S(1));
      worst = std::fmax(worst, rel);
      if (!(rel <= double(tol)) && bad++ < 5)
        std::printf("  %s row %d entry %d: %.17g on the host, %.17g on the device\n", name, r, j, double(h[j]),
                    double(d[j]));
    }
  }
  std::printf("%s: %d rows (%d ok), largest difference %.3g of the row's largest entry (bound %.3g): %s\n", name,
              kRows * kKinds, ok_rows, worst, double(tol), bad ? "FAIL" : "pass");
  return bad ? 1 : 0;
}

}  // namespace

int main() {
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    std::printf("skipped: no CUDA device\n");
    return 77;
  }
  return compare<double>("double") | compare<float>("float");
}
