// SPDX-License-Identifier: MIT
// A batch of vertex-face pairs evaluated in a CUDA kernel, one pair per thread: the energy,
// the gradient and the analytic projected Hessian, through `pce::evaluate_batch_row` (what
// `pce::evaluate_batch` does for each row on the host). Prints pair 0's outputs beside the
// host's; without a CUDA device it says so and exits 0.
//
//     cmake -S . -B build -DPCE_CUDA=ON && cmake --build build --target cuda_batch
//     build/examples/cuda_batch/cuda_batch
#include <pce/pce.hpp>

#include <cuda_runtime.h>

#include <cstdio>
#include <vector>

// Thread i evaluates pair i: 12 coordinates at x + 12 i, outputs at row i of `out`.
__global__ void vertex_face_batch(const double* x, int count, pce::BatchOutput<double> out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const pce::QuadraticPenalty penalty{1e3, 1e-2};  // k (L - 0.01)^2 below L = 0.01
  pce::evaluate_batch_row<pce::VertexFace>(x, std::size_t(i), pce::SignedLength{}, penalty, pce::Projection::analytic,
                                           out);
}

int main() {
  const int count = 1024;
  std::vector<double> x(12 * count);
  for (int i = 0; i < count; ++i) {  // a unit triangle and a vertex 0 to 9 mm above it
    const double p[12] = {0.2, 0.3, 0.009 * i / count, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (int c = 0; c < 12; ++c) x[12 * i + c] = p[c];
  }
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    std::printf("skipped: no CUDA device\n");
    return 0;
  }
  double *dx, *value, *gradient, *hessian;
  pce::Status* status;
  cudaMalloc(&dx, x.size() * sizeof(double));
  cudaMalloc(&value, count * sizeof(double));
  cudaMalloc(&gradient, 12 * count * sizeof(double));
  cudaMalloc(&hessian, 144 * count * sizeof(double));
  cudaMalloc(&status, count * sizeof(pce::Status));
  cudaMemcpy(dx, x.data(), x.size() * sizeof(double), cudaMemcpyHostToDevice);
  pce::BatchOutput<double> out;
  out.status = status, out.value = value, out.gradient = gradient, out.projected = hessian;
  vertex_face_batch<<<(count + 127) / 128, 128>>>(dx, count, out);
  if (cudaDeviceSynchronize() != cudaSuccess) {
    std::printf("the kernel failed\n");
    return 1;
  }
  double e0, g0[12];
  cudaMemcpy(&e0, value, sizeof(double), cudaMemcpyDeviceToHost);
  cudaMemcpy(g0, gradient, sizeof(g0), cudaMemcpyDeviceToHost);
  // the same pair on the host
  pce::PairEnergy<double> e;
  pce::pair_energy<pce::VertexFace>(pce::Vec12<double>(x.data()), pce::SignedLength{}, pce::QuadraticPenalty{1e3, 1e-2},
                                    e);
  std::printf("pair 0: energy %.12g (host %.12g), dE/dp_z %.12g (host %.12g)\n", e0, e.psi.value, g0[2],
              pce::energy_gradient(e)[2]);
  cudaFree(dx), cudaFree(value), cudaFree(gradient), cudaFree(hessian), cudaFree(status);
  return 0;
}
