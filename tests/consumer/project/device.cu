// SPDX-License-Identifier: MIT
// What a solver writer's CUDA file does with the installed pce: a kernel calling the pair
// energy, its gradient and projected_hessian<analytic> for vertex-face and edge-edge, in float
// and double. Built by the consumer test `consumer_find_package_cuda` (../CMakeLists.txt); it
// must compile against the installed package. Run: without a CUDA device it says so and exits
// 0; with one, each pair's energy, gradient norm and projected Hessian's trace must match the
// host's to 1e-4 relative.
#include <pce/pce.hpp>

#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>

// out[0] energy, out[1] the gradient's squared norm, out[2] the projected Hessian's trace;
// out[0] = NaN when the pair is not ok.
template <class Pair, class Scalar, class Length, class Penalty>
__host__ __device__ void evaluate(const Scalar* xp, const Length& length, const Penalty& penalty, Scalar* out) {
  const pce::Vec12<Scalar> x(xp);
  pce::PairEnergy<Scalar> e;
  if (pce::pair_energy<Pair>(x, length, penalty, e) != pce::Status::ok) {
    out[0] = Scalar(NAN);
    return;
  }
  const pce::Vec12<Scalar> g = pce::energy_gradient(e);
  const pce::Mat12<Scalar> h = pce::projected_hessian<pce::Projection::analytic>(e);
  out[0] = e.psi.value;
  out[1] = g.squaredNorm();
  out[2] = h.trace();
}

// Pair 0: a vertex 4 mm above a triangle, signed length, quadratic penalty; pair 1: two
// crossing edges 3 mm apart, unsigned length, log barrier.
template <class Scalar> __host__ __device__ void both(const Scalar* x, Scalar* out) {
  evaluate<pce::VertexFace>(x, pce::SignedLength{}, pce::QuadraticPenalty{1e3, 1e-2}, out);
  evaluate<pce::EdgeEdge>(x + 12, pce::UnsignedLength{}, pce::LogBarrierPenalty{1.0, 1e-2}, out + 3);
}

template <class Scalar> __global__ void kernel(const Scalar* x, Scalar* out) { both(x, out); }

template <class Scalar> int run(const char* name) {
  // clang-format off
  const Scalar x[24] = {Scalar(0.2), Scalar(0.3), Scalar(0.004), 0, 0, 0, 1, 0, 0, 0, 1, 0,  // vertex, triangle
                        0, 0, 0, 1, 0, 0,                                                   // edge a
                        Scalar(0.5), Scalar(-0.5), Scalar(0.003), Scalar(0.5), Scalar(0.5), Scalar(0.003)};  // edge b
  // clang-format on
  Scalar host[6], device[6];
  both(x, host);
  Scalar *dx, *dout;
  cudaMalloc(&dx, sizeof(x));
  cudaMalloc(&dout, sizeof(device));
  cudaMemcpy(dx, x, sizeof(x), cudaMemcpyHostToDevice);
  kernel<Scalar><<<1, 1>>>(dx, dout);
  const bool launched = cudaDeviceSynchronize() == cudaSuccess;
  if (launched) cudaMemcpy(device, dout, sizeof(device), cudaMemcpyDeviceToHost);
  cudaFree(dx), cudaFree(dout);
  if (!launched) {
    std::printf("%s: the kernel failed\n", name);
    return 1;
  }
  int bad = 0;
  for (int k = 0; k < 6; ++k) {
    const bool ok = std::abs(device[k] - host[k]) <= Scalar(1e-4) * std::abs(host[k]);  // false for NaN
    std::printf("%s %s %d: device %.9g host %.9g%s\n", name, k < 3 ? "vertex_face" : "edge_edge", k % 3,
                double(device[k]), double(host[k]), ok ? "" : "  MISMATCH");
    bad += ok ? 0 : 1;
  }
  return bad;
}

int main() {
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    std::printf("consumer_cuda: compiled; skipped: no CUDA device\n");
    return 0;
  }
  return (run<float>("float") + run<double>("double")) == 0 ? 0 : 1;
}
