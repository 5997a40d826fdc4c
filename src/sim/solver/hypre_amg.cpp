// SPDX-License-Identifier: MIT
// BoomerAMG as conjugate gradients' preconditioner (hypre_amg.hpp). The only file that
// includes hypre or MPI.
//
// MPI: hypre's ParCSR objects live on MPI_COMM_SELF (one rank, whatever the process does).
// The first setup calls MPI_Init_thread (MPI_THREAD_FUNNELED: only the thread that calls
// pce::sim uses MPI) unless MPI is initialised already, e.g. by a program that runs under
// mpirun. pce::sim never calls MPI_Finalize: a library cannot know whether its caller still
// needs MPI, and a destructor of a static Simulation may run after the program (or an atexit
// handler) finalised it. The process exits without finalising when pce::sim initialised MPI;
// Open MPI's singleton mode cleans up at exit. After someone else's MPI_Finalize, setup fails.
#include "solver/hypre_amg.hpp"

#ifdef PCE_SIM_HAVE_HYPRE
#include <HYPRE.h>
#include <HYPRE_parcsr_ls.h>
#include <mpi.h>

#include <Eigen/Geometry>

#include <array>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>
#endif

namespace pce::sim::solver {

#ifdef PCE_SIM_HAVE_HYPRE

bool hypre_available() { return true; }

namespace {

/// MPI initialised (by us, once, or by the program) and hypre's run time started; false after
/// MPI_Finalize.
bool start_mpi() {
  static std::once_flag once;
  std::call_once(once, [] {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    }
    HYPRE_Init();
  });
  int finalized = 0;
  MPI_Finalized(&finalized);
  return !finalized;
}

/// An integer setting from the environment (the measurement knobs below), else `fallback`.
long env_integer(const char* name, long fallback) {
  const char* text = std::getenv(name);
  return text && *text ? std::strtol(text, nullptr, 10) : fallback;
}

/// A number from the environment, else `fallback`.
double env_number(const char* name, double fallback) {
  const char* text = std::getenv(name);
  return text && *text ? std::strtod(text, nullptr) : fallback;
}

}  // namespace

/// hypre's matrix, vectors and solver, with the arrays the matrix is copied from.
struct HypreAmg::State {
  HYPRE_IJMatrix A = nullptr;
  HYPRE_IJVector b = nullptr, x = nullptr;
  std::array<HYPRE_IJVector, 3> modes{};  ///< the rotation modes, while the size stays
  bool have_modes = false;                ///< `modes` hold this setup's rotations
  HYPRE_Solver amg = nullptr;
  HYPRE_BigInt size = 0;
  std::vector<HYPRE_Int> row_sizes;
  std::vector<HYPRE_BigInt> rows, cols, index;
  std::vector<double> values;

  /// Frees the matrix and the solver (the vectors stay while the size does).
  void release() {
    if (amg) HYPRE_BoomerAMGDestroy(amg);
    if (A) HYPRE_IJMatrixDestroy(A);
    amg = nullptr;
    A = nullptr;
  }
  /// Frees everything.
  ~State() {
    release();
    if (b) HYPRE_IJVectorDestroy(b);
    if (x) HYPRE_IJVectorDestroy(x);
    for (HYPRE_IJVector& m : modes)
      if (m) HYPRE_IJVectorDestroy(m);
  }
  /// modes[k] = eₖ × (xᵢ − x̄) at every vertex i (rotations about the centroid x̄).
  void set_modes(const Eigen::Matrix3Xd& positions);
  /// A vector of `size` entries on MPI_COMM_SELF.
  HYPRE_IJVector make_vector() const {
    HYPRE_IJVector v = nullptr;
    HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, size - 1, &v);
    HYPRE_IJVectorSetObjectType(v, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(v);
    HYPRE_IJVectorAssemble(v);
    return v;
  }
  /// `H`'s scalar rows in CSR arrays (row 3i + r: row i's blocks' row r, in column order).
  void copy(const BlockCsr& H);
  /// hypre's IJ matrix from the arrays; false on a hypre error.
  bool assemble();
  /// BoomerAMG as one V-cycle, set up on A; false on a hypre error.
  bool setup_amg();
};

void HypreAmg::State::copy(const BlockCsr& H) {
  const int n = H.vertex_count();
  size = 3 * static_cast<HYPRE_BigInt>(n);
  const std::size_t entries = 9 * H.columns().size();
  row_sizes.resize(static_cast<std::size_t>(size));
  rows.resize(static_cast<std::size_t>(size));
  cols.resize(entries);
  values.resize(entries);
  std::size_t at = 0;
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < 3; ++r) {
      const auto row = static_cast<std::size_t>(3 * i + r);
      rows[row] = static_cast<HYPRE_BigInt>(row);
      const int first = H.row_begin()[static_cast<std::size_t>(i)],
                last = H.row_begin()[static_cast<std::size_t>(i) + 1];
      row_sizes[row] = static_cast<HYPRE_Int>(3 * (last - first));
      for (int k = first; k < last; ++k)
        for (int c = 0; c < 3; ++c) {
          cols[at] = 3 * static_cast<HYPRE_BigInt>(H.columns()[static_cast<std::size_t>(k)]) + c;
          values[at++] = H.values()[9 * static_cast<std::size_t>(k) + static_cast<std::size_t>(3 * r + c)];
        }
    }
}

bool HypreAmg::State::assemble() {
  HYPRE_Int error = HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, size - 1, 0, size - 1, &A);
  error |= HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR);
  error |= HYPRE_IJMatrixSetRowSizes(A, row_sizes.data());
  error |= HYPRE_IJMatrixInitialize(A);
  error |= HYPRE_IJMatrixSetValues(A, static_cast<HYPRE_Int>(size), row_sizes.data(), rows.data(), cols.data(),
                                   values.data());
  error |= HYPRE_IJMatrixAssemble(A);
  return error == 0;
}

bool HypreAmg::State::setup_amg() {
  HYPRE_ParCSRMatrix parcsr = nullptr;
  HYPRE_ParVector pb = nullptr, px = nullptr;
  HYPRE_IJMatrixGetObject(A, reinterpret_cast<void**>(&parcsr));
  HYPRE_IJVectorGetObject(b, reinterpret_cast<void**>(&pb));
  HYPRE_IJVectorGetObject(x, reinterpret_cast<void**>(&px));
  HYPRE_BoomerAMGCreate(&amg);
  HYPRE_BoomerAMGSetPrintLevel(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_PRINT", 0)));
  HYPRE_BoomerAMGSetMaxIter(amg, 1);  // one V-cycle per application, from zero
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  // Systems AMG: unknowns 3i, 3i+1, 3i+2 are vertex i's (hypre's default ordering).
  HYPRE_BoomerAMGSetNumFunctions(amg, 3);
  // The environment variables are measurement knobs (docs/simulation.md §5.3), each
  // defaulting to what measured best on the scale ladder's 8k systems: coarsening by
  // unknown (nodal 0), strength threshold 0.25, the symmetric hybrid Gauss–Seidel smoother
  // (6: the V-cycle is symmetric, as CG needs), HMIS coarsening (10) with one level of
  // aggressive coarsening (setup 75 -> 37 ms, 17 -> 28 iterations), extended+i
  // interpolation (6) of at most 4 entries per row.
  HYPRE_BoomerAMGSetNodal(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_NODAL", 0)));
  HYPRE_BoomerAMGSetStrongThreshold(amg, env_number("PCE_SIM_AMG_STRONG", 0.25));
  HYPRE_BoomerAMGSetRelaxType(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_RELAX", 6)));
  HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3);  // Gaussian elimination on the coarsest level
  HYPRE_BoomerAMGSetAggNumLevels(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_AGGRESSIVE", 1)));
  HYPRE_BoomerAMGSetCoarsenType(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_COARSEN", 10)));
  HYPRE_BoomerAMGSetInterpType(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_INTERP", 6)));
  HYPRE_BoomerAMGSetPMaxElmts(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_PMAX", 4)));
  std::array<HYPRE_ParVector, 3> parmodes{};
  if (have_modes) {
    // Interpolation vectors need nodal coarsening (hypre's BoomerAMGSetInterpVectors).
    for (std::size_t k = 0; k < 3; ++k) HYPRE_IJVectorGetObject(modes[k], reinterpret_cast<void**>(&parmodes[k]));
    HYPRE_BoomerAMGSetNodal(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_RBM_NODAL", 4)));
    HYPRE_BoomerAMGSetInterpVectors(amg, 3, parmodes.data());
    HYPRE_BoomerAMGSetInterpVecVariant(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_RBM_VARIANT", 2)));
    HYPRE_BoomerAMGSetInterpVecQMax(amg, static_cast<HYPRE_Int>(env_integer("PCE_SIM_AMG_RBM_QMAX", 4)));
  }
  const HYPRE_Int error = HYPRE_BoomerAMGSetup(amg, parcsr, pb, px);
  HYPRE_ClearAllErrors();
  return error == 0;
}

HypreAmg::HypreAmg() : state_(std::make_unique<State>()) {}
HypreAmg::~HypreAmg() = default;

void HypreAmg::State::set_modes(const Eigen::Matrix3Xd& positions) {
  const Eigen::Vector3d centre = positions.rowwise().mean();
  std::vector<double> v(static_cast<std::size_t>(size));
  for (std::size_t k = 0; k < 3; ++k) {
    if (!modes[k]) modes[k] = make_vector();
    const Eigen::Vector3d axis = Eigen::Vector3d::Unit(static_cast<Eigen::Index>(k));
    for (Eigen::Index i = 0; i < positions.cols(); ++i) {
      const Eigen::Vector3d m = axis.cross(positions.col(i) - centre);
      for (Eigen::Index c = 0; c < 3; ++c) v[static_cast<std::size_t>(3 * i + c)] = m[c];
    }
    HYPRE_IJVectorSetValues(modes[k], static_cast<HYPRE_Int>(size), index.data(), v.data());
  }
  have_modes = true;
}

bool HypreAmg::setup(const BlockCsr& H, const Eigen::Matrix3Xd* positions) {
  if (!start_mpi()) return false;
  State& s = *state_;
  const HYPRE_BigInt size = 3 * static_cast<HYPRE_BigInt>(H.vertex_count());
  s.release();
  if (size != s.size || !s.b) {
    if (s.b) HYPRE_IJVectorDestroy(s.b);
    if (s.x) HYPRE_IJVectorDestroy(s.x);
    for (HYPRE_IJVector& m : s.modes) {
      if (m) HYPRE_IJVectorDestroy(m);
      m = nullptr;
    }
    s.size = size;
    s.b = s.make_vector();
    s.x = s.make_vector();
    s.index.resize(static_cast<std::size_t>(size));
    for (HYPRE_BigInt i = 0; i < size; ++i) s.index[static_cast<std::size_t>(i)] = i;
  }
  s.have_modes = false;
  if (positions && 3 * positions->cols() == size && env_integer("PCE_SIM_AMG_RBM", 1) != 0) s.set_modes(*positions);
  s.copy(H);
  if (!s.assemble() || !s.setup_amg()) {
    s.release();
    return false;
  }
  return true;
}

bool HypreAmg::ready() const { return state_->amg != nullptr; }

void HypreAmg::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  State& s = *state_;
  const auto size = static_cast<HYPRE_Int>(s.size);
  z.setZero(r.size());
  HYPRE_IJVectorSetValues(s.b, size, s.index.data(), r.data());
  HYPRE_IJVectorSetValues(s.x, size, s.index.data(), z.data());  // the V-cycle starts at zero
  HYPRE_ParCSRMatrix parcsr = nullptr;
  HYPRE_ParVector pb = nullptr, px = nullptr;
  HYPRE_IJMatrixGetObject(s.A, reinterpret_cast<void**>(&parcsr));
  HYPRE_IJVectorGetObject(s.b, reinterpret_cast<void**>(&pb));
  HYPRE_IJVectorGetObject(s.x, reinterpret_cast<void**>(&px));
  HYPRE_BoomerAMGSolve(s.amg, parcsr, pb, px);
  HYPRE_ClearAllErrors();
  HYPRE_IJVectorGetValues(s.x, size, s.index.data(), z.data());
}

#else  // no hypre: amg is not available and its setup fails.

bool hypre_available() { return false; }

struct HypreAmg::State {};
HypreAmg::HypreAmg() : state_(std::make_unique<State>()) {}
HypreAmg::~HypreAmg() = default;
bool HypreAmg::setup(const BlockCsr&, const Eigen::Matrix3Xd*) { return false; }
bool HypreAmg::ready() const { return false; }
void HypreAmg::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const { z = r; }

#endif

}  // namespace pce::sim::solver
