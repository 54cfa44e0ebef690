// BoomerAMG preconditioner for the PPE (see ppe_hypre.hpp).
#include "schemes/isph/ppe_hypre.hpp"

// The C API only: Open MPI's mpi.h would pull in its C++ bindings (libmpi_cxx) otherwise.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

namespace {

// MPI and HYPRE are initialised once per process, on first use, and finalised at exit when we
// initialised them (a host program that runs MPI itself keeps control of it).
void hypre_init_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited) {
      // Open MPI's singleton would fork an orted daemon otherwise.
      setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
      int provided = 0;
      if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        throw std::runtime_error("PPE: MPI_Init failed (HYPRE needs MPI)");
      std::atexit([] {
        HYPRE_Finalize();
        int fin = 0;
        MPI_Finalized(&fin);
        if (!fin)
          MPI_Finalize();
      });
    }
    HYPRE_Init();
  });
}

void check(HYPRE_Int err, const char* what) {
  if (err) {
    char msg[256] = {0};
    HYPRE_DescribeError(err, msg);
    HYPRE_ClearAllErrors();
    throw std::runtime_error(std::string("PPE: HYPRE ") + what + " failed: " + msg);
  }
}

} // namespace

struct HypreAmg::Impl {
  HYPRE_IJMatrix ij_a = nullptr;
  HYPRE_IJVector ij_b = nullptr, ij_x = nullptr;
  HYPRE_ParCSRMatrix a = nullptr;
  HYPRE_ParVector b = nullptr, x = nullptr;
  HYPRE_Solver amg = nullptr;
  std::vector<HYPRE_Int> rows, ncols;

  void free_matrix() {
    if (amg)
      HYPRE_BoomerAMGDestroy(amg), amg = nullptr;
    if (ij_a)
      HYPRE_IJMatrixDestroy(ij_a), ij_a = nullptr, a = nullptr;
  }
  void free_vectors() {
    if (ij_b)
      HYPRE_IJVectorDestroy(ij_b), ij_b = nullptr, b = nullptr;
    if (ij_x)
      HYPRE_IJVectorDestroy(ij_x), ij_x = nullptr, x = nullptr;
  }
  ~Impl() {
    free_matrix();
    free_vectors();
  }
};

HypreAmg::HypreAmg(const AmgSettings& s) : impl_(std::make_unique<Impl>()), settings_(s) {
  hypre_init_once();
}

HypreAmg::~HypreAmg() = default;

void HypreAmg::setup(const RowMat& a) {
  Impl& m = *impl_;
  const int n = static_cast<int>(a.rows());
  m.free_matrix();
  if (n != n_ || !m.ij_b) {
    m.free_vectors();
    for (HYPRE_IJVector* v : {&m.ij_b, &m.ij_x}) {
      check(HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, v), "IJVectorCreate");
      HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
      HYPRE_IJVectorInitialize(*v);
      HYPRE_IJVectorAssemble(*v);
    }
    HYPRE_IJVectorGetObject(m.ij_b, reinterpret_cast<void**>(&m.b));
    HYPRE_IJVectorGetObject(m.ij_x, reinterpret_cast<void**>(&m.x));
    n_ = n;
  }
  // The matrix: one SetValues call with all rows (HYPRE_Int is int in Debian's 32-bit build).
  static_assert(sizeof(HYPRE_Int) == sizeof(int) && sizeof(HYPRE_BigInt) == sizeof(int),
                "libhypre-dev (32-bit indices) expected");
  const int* off = a.outerIndexPtr();
  m.rows.resize(n), m.ncols.resize(n);
  for (int i = 0; i < n; ++i)
    m.rows[i] = i, m.ncols[i] = off[i + 1] - off[i];
  check(HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, n - 1, 0, n - 1, &m.ij_a), "IJMatrixCreate");
  HYPRE_IJMatrixSetObjectType(m.ij_a, HYPRE_PARCSR);
  HYPRE_IJMatrixSetRowSizes(m.ij_a, m.ncols.data());
  HYPRE_IJMatrixInitialize(m.ij_a);
  check(HYPRE_IJMatrixSetValues(m.ij_a, n, m.ncols.data(), m.rows.data(),
                                const_cast<HYPRE_BigInt*>(a.innerIndexPtr()), a.valuePtr()),
        "IJMatrixSetValues");
  check(HYPRE_IJMatrixAssemble(m.ij_a), "IJMatrixAssemble");
  HYPRE_IJMatrixGetObject(m.ij_a, reinterpret_cast<void**>(&m.a));

  const AmgSettings& s = settings_;
  HYPRE_BoomerAMGCreate(&m.amg);
  HYPRE_BoomerAMGSetPrintLevel(m.amg, 0);
  HYPRE_BoomerAMGSetCoarsenType(m.amg, s.coarsen_type);
  HYPRE_BoomerAMGSetInterpType(m.amg, s.interp_type);
  HYPRE_BoomerAMGSetStrongThreshold(m.amg, s.strong_threshold);
  HYPRE_BoomerAMGSetAggNumLevels(m.amg, s.agg_num_levels);
  HYPRE_BoomerAMGSetCycleRelaxType(m.amg, s.relax_down, 1);
  HYPRE_BoomerAMGSetCycleRelaxType(m.amg, s.relax_up, 2);
  HYPRE_BoomerAMGSetCycleRelaxType(m.amg, s.relax_coarse, 3);
  HYPRE_BoomerAMGSetNumSweeps(m.amg, s.num_sweeps);
  HYPRE_BoomerAMGSetPMaxElmts(m.amg, s.p_max_elmts);
  HYPRE_BoomerAMGSetMaxIter(m.amg, 1); // as a preconditioner: one V-cycle
  HYPRE_BoomerAMGSetTol(m.amg, 0.0);
  check(HYPRE_BoomerAMGSetup(m.amg, m.a, m.b, m.x), "BoomerAMGSetup");
}

void HypreAmg::apply(const double* in, double* out) const {
  Impl& m = *impl_;
  double* b = hypre_VectorData(hypre_ParVectorLocalVector(m.b));
  double* x = hypre_VectorData(hypre_ParVectorLocalVector(m.x));
  std::memcpy(b, in, sizeof(double) * n_);
  std::memset(x, 0, sizeof(double) * n_);
  HYPRE_BoomerAMGSolve(m.amg, m.a, m.b, m.x);
  std::memcpy(out, x, sizeof(double) * n_);
}

int HypreAmg::levels() const {
  if (!impl_->amg)
    return 0;
  return hypre_ParAMGDataNumLevels(reinterpret_cast<hypre_ParAMGData*>(impl_->amg));
}

double HypreAmg::operator_complexity() const {
  if (!impl_->amg)
    return 0.0;
  auto* d = reinterpret_cast<hypre_ParAMGData*>(impl_->amg);
  const int nl = hypre_ParAMGDataNumLevels(d);
  hypre_ParCSRMatrix** A = hypre_ParAMGDataAArray(d);
  double nnz0 = 0.0, total = 0.0;
  for (int l = 0; l < nl; ++l) {
    const double z = static_cast<double>(hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixDiag(A[l])));
    total += z;
    if (l == 0)
      nnz0 = z;
  }
  return nnz0 > 0.0 ? total / nnz0 : 0.0;
}

} // namespace sph
