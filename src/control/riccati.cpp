#include "control/riccati.h"

#include <Eigen/LU>
#include <algorithm>
#include <vector>

extern "C" {
// SLICOT SB02OD (Fortran 77). Hidden string lengths are passed last, by value.
void sb02od_(const char* dico, const char* jobb, const char* fact, const char* uplo,
             const char* jobl, const char* sort, const int* n, const int* m, const int* p,
             const double* a, const int* lda, const double* b, const int* ldb, const double* q,
             const int* ldq, const double* r, const int* ldr, const double* l, const int* ldl,
             double* rcond, double* x, const int* ldx, double* alfar, double* alfai,
             double* beta, double* s, const int* lds, double* t, const int* ldt, double* u,
             const int* ldu, const double* tol, int* iwork, double* dwork, const int* ldwork,
             int* bwork, int* info, std::size_t, std::size_t, std::size_t, std::size_t,
             std::size_t, std::size_t);
}

namespace quadfdi {

RiccatiResult solveDiscreteRiccati(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                   const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  RiccatiResult result;
  const int n = static_cast<int>(A.rows());
  const int m = static_cast<int>(B.cols());
  if (A.cols() != n || B.rows() != n || Q.rows() != n || Q.cols() != n || R.rows() != m ||
      R.cols() != m || n == 0 || m == 0) {
    result.info = -1;
    result.message = "inconsistent matrix sizes";
    return result;
  }
  const int p = 0;
  const int lds = 2 * n + m, ldt = 2 * n + m, ldu = 2 * n;
  // Column-major copies: SLICOT may overwrite its inputs.
  Eigen::MatrixXd a = A, b = B, q = Q, r = R, l = Eigen::MatrixXd::Zero(n, m);
  Eigen::MatrixXd x(n, n);
  std::vector<double> alfar(2 * n), alfai(2 * n), beta(2 * n);
  std::vector<double> s(static_cast<std::size_t>(lds) * (2 * n + m));
  std::vector<double> t(static_cast<std::size_t>(ldt) * (2 * n));
  std::vector<double> u(static_cast<std::size_t>(ldu) * (2 * n));
  std::vector<int> iwork(std::max({1, m, 2 * n}));
  // SB02OD documents LDWORK >= max(7(2N+1)+16, 16N, 2N+M, 3M); generous for blocking.
  const int ldwork = std::max({7 * (2 * n + 1) + 16, 16 * n, 2 * n + m, 3 * m}) * 8;
  std::vector<double> dwork(ldwork);
  std::vector<int> bwork(2 * n);
  const double tol = 0.0;  // SLICOT's default tolerance
  sb02od_("D", "B", "N", "U", "Z", "S", &n, &m, &p, a.data(), &n, b.data(), &n, q.data(), &n,
          r.data(), &m, l.data(), &n, &result.rcond, x.data(), &n, alfar.data(), alfai.data(),
          beta.data(), s.data(), &lds, t.data(), &ldt, u.data(), &ldu, &tol, iwork.data(),
          dwork.data(), &ldwork, bwork.data(), &result.info, 1, 1, 1, 1, 1, 1);
  if (result.info != 0) {
    result.message = "SLICOT SB02OD failed with INFO = " + std::to_string(result.info);
    return result;
  }
  result.X = 0.5 * (x + x.transpose());  // symmetric by construction; remove round-off skew
  return result;
}

double discreteRiccatiResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                               const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                               const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd btxa = B.transpose() * X * A;
  const Eigen::MatrixXd gain = (R + B.transpose() * X * B).lu().solve(btxa);
  const Eigen::MatrixXd res = A.transpose() * X * A - X - btxa.transpose() * gain + Q;
  return res.norm() / std::max(1.0, X.norm());
}

}  // namespace quadfdi
