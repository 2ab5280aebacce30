// Small, exact, allocation-free dense QP solver for the per-step CBF-QP safety
// filter (4 motor thrusts, 8 bounds, a few CBF rows, solved every 2 ms).
//
//   minimise    ½ xᵀ H x + gᵀ x                 H symmetric positive definite
//   subject to  A.row(i) x >= b(i),  i < num_rows
//               lower <= x <= upper              (±infinity allowed)
//
// Algorithm: the dual active-set method of
//   D. Goldfarb, A. Idnani, "A numerically stable dual method for solving
//   strictly convex quadratic programs", Math. Programming 27 (1983) 1-33,
// in its numerically stable product form: with H = L Lᵀ, the matrices
// J = L⁻ᵀQ and R (Q R the QR factorisation of L⁻¹ times the active normals)
// are updated by Givens rotations as constraints enter and leave. It was
// chosen over a primal active-set or first-order method because
//   * it needs no feasible starting point (no phase 1): it starts at the
//     unconstrained minimiser and adds violated constraints one at a time, each
//     iterate being the exact optimum over the constraints active so far;
//   * infeasibility is detected exactly: it is declared only when a violated
//     constraint can be neither stepped towards (primal) nor made room for by
//     dropping an active one (dual), which is a certificate that the
//     constraints are inconsistent;
//   * it is exact and finite, and for N = 4 a solve is a handful of rank-one
//     updates on 4x4 matrices.
// Every bound is treated internally as an extra inequality row, so there are at
// most M + 2N constraints; general rows are scaled to unit norm so that
// tolerances mean distances in x and the "most violated" choice is scale-free.
//
// Everything lives on the stack in fixed-size Eigen types; parts whose length
// depends on the active-set size are plain loops, so solve() never allocates.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace quadfdi {

enum class QpStatus { kSolved, kInfeasible, kMaxIterations, kInvalidInput };

inline const char* toString(QpStatus s) {
  switch (s) {
    case QpStatus::kSolved: return "solved";
    case QpStatus::kInfeasible: return "infeasible";
    case QpStatus::kMaxIterations: return "max_iterations";
    case QpStatus::kInvalidInput: return "invalid_input";
  }
  return "unknown";
}

// Data default to an invalid H (zero) and absent bounds, so a problem that is
// not filled in is rejected instead of solved with uninitialised memory.
template <int N, int M>
struct QpProblem {
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();  // symmetric positive definite
  Eigen::Matrix<double, N, 1> g = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, M, N> A = Eigen::Matrix<double, M, N>::Zero();
  Eigen::Matrix<double, M, 1> b = Eigen::Matrix<double, M, 1>::Zero();
  int num_rows = M;  // only the first num_rows rows of A, b are constraints (0..M)
  Eigen::Matrix<double, N, 1> lower =
      Eigen::Matrix<double, N, 1>::Constant(-std::numeric_limits<double>::infinity());
  Eigen::Matrix<double, N, 1> upper =
      Eigen::Matrix<double, N, 1>::Constant(std::numeric_limits<double>::infinity());
};

// Multipliers satisfy H x + g − Aᵀ row − lower_mult + upper_mult = 0.
// On kInfeasible / kMaxIterations, x is the last (finite) iterate: the optimum
// over the constraints that were active, NOT a feasible point. On
// kInvalidInput everything is zero. Callers must check the status.
template <int N, int M>
struct QpSolution {
  Eigen::Matrix<double, N, 1> x = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, M, 1> row_multipliers = Eigen::Matrix<double, M, 1>::Zero();    // >= 0, for A x >= b
  Eigen::Matrix<double, N, 1> lower_multipliers = Eigen::Matrix<double, N, 1>::Zero();  // >= 0
  Eigen::Matrix<double, N, 1> upper_multipliers = Eigen::Matrix<double, N, 1>::Zero();  // >= 0
  int iterations = 0;  // add + drop steps of the active set
  QpStatus status = QpStatus::kInvalidInput;
};

// Outside the class template because a nested struct with default member
// initialisers cannot be used as a default argument inside its enclosing class.
struct QpSettings {
  // Each add or drop of a constraint is one iteration. The method is finite;
  // this only bounds the work if rounding ever makes it cycle.
  int max_iterations = 100;
  // A constraint counts as violated when its unit-normal slack is below
  // −feasibility_tol · max(1, |b|/‖a‖); relative for large right-hand sides
  // because the slack cannot be computed more accurately than that.
  double feasibility_tol = 1e-10;
  // A constraint is treated as linearly dependent on the active ones when its
  // component outside their span (in the H⁻¹ metric) is below
  // dependency_tol · ‖L⁻ᵀ‖_F. Stepping along such a direction would only
  // amplify rounding error.
  double dependency_tol = 1e-10;
  // H is rejected if max|H − Hᵀ| > symmetry_tol · max|H|: only its lower
  // triangle is read, so a clearly asymmetric H signals a caller bug.
  double symmetry_tol = 1e-9;
  // H is rejected if its smallest Cholesky pivot L_ii² is below
  // min_pivot_ratio · max H_ii. This ratio is >= 1/cond(H), so only
  // numerically singular matrices fail.
  double min_pivot_ratio = 1e-12;
};

template <int N, int M>
class DenseQpSolver {
  static_assert(N >= 1, "QP needs at least one variable");
  static_assert(M >= 0, "number of general rows cannot be negative");

 public:
  using Settings = QpSettings;
  using Problem = QpProblem<N, M>;
  using Solution = QpSolution<N, M>;

  explicit DenseQpSolver(Settings s = {}) : settings_(s) {}

  const Settings& settings() const { return settings_; }

  QpStatus solve(const Problem& problem, Solution& solution) const;

 private:
  // Internal constraint k: rows k in [0, M), lower bounds [M, M+N), upper
  // bounds [M+N, M+2N). All are n_kᵀ x >= c_k with ‖n_k‖ = 1.
  static constexpr int K = M + 2 * N;
  using VecN = Eigen::Matrix<double, N, 1>;
  using MatN = Eigen::Matrix<double, N, N>;

  struct Constraints {
    Eigen::Matrix<double, N, K> normal;
    double rhs[K];
    double row_norm[K];  // ‖A.row(k)‖ for rows, 1 for bounds; maps multipliers back
    bool enabled[K];     // false: row beyond num_rows, zero row, or infinite bound
  };

  // Active set and the Goldfarb-Idnani factorisation. With N_A the active
  // normals (in order), the invariant is Jᵀ N_A = [R; 0], J Jᵀ = H⁻¹, R upper
  // triangular q x q. Columns q.. of J span the directions that keep the
  // active constraints' values fixed.
  struct ActiveSet {
    MatN J;
    MatN R;
    int index[N];  // internal constraint number of each active entry
    double u[N];   // its multiplier (>= 0)
    bool is_active[K];
    int q = 0;
  };

  bool validate(const Problem& p) const;
  static void addConstraint(ActiveSet& as, int k, double multiplier, VecN& d);
  static void dropConstraint(ActiveSet& as, int position);
  static void writeSolution(const Constraints& c, const ActiveSet& as, const VecN& x, Solution& solution);
  double violationTol(double rhs) const { return settings_.feasibility_tol * std::max(1.0, std::abs(rhs)); }

  Settings settings_;
};

// ---------------------------------------------------------------------------

template <int N, int M>
bool DenseQpSolver<N, M>::validate(const Problem& p) const {
  if (p.num_rows < 0 || p.num_rows > M) return false;
  // Rows beyond num_rows are deliberately not inspected: callers may leave
  // them stale.
  if (!p.H.allFinite() || !p.g.allFinite()) return false;
  for (int i = 0; i < p.num_rows; ++i) {
    if (!p.A.row(i).allFinite() || !std::isfinite(p.b(i))) return false;
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int j = 0; j < N; ++j) {
    // NaN fails both comparisons below; +inf lower / −inf upper is empty.
    if (!(p.lower(j) < kInf) || !(p.upper(j) > -kInf)) return false;
    if (!(p.lower(j) <= p.upper(j))) return false;
  }
  const double h_max = p.H.cwiseAbs().maxCoeff();
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < i; ++j) {
      if (std::abs(p.H(i, j) - p.H(j, i)) > settings_.symmetry_tol * h_max) return false;
    }
  }
  return true;
}

// Appends constraint k whose d = Jᵀ n_k is given. Rotations zero d(q+1..N−1)
// into d(q), applied to the matching columns of J, which keeps Jᵀ N_A = [R; 0]
// for the old active set (their entries in those rows are zero) and makes the
// new column of R equal to d(0..q). The caller guarantees that n_k is not in
// the span of the active normals, so the new diagonal d(q) is nonzero.
template <int N, int M>
void DenseQpSolver<N, M>::addConstraint(ActiveSet& as, int k, double multiplier, VecN& d) {
  const int q = as.q;
  for (int j = N - 1; j > q; --j) {
    const double a = d(j - 1);
    const double b = d(j);
    if (b == 0.0) continue;
    const double h = std::hypot(a, b);
    const double c = a / h;
    const double s = b / h;
    d(j - 1) = h;
    d(j) = 0.0;
    for (int i = 0; i < N; ++i) {
      const double ja = as.J(i, j - 1);
      const double jb = as.J(i, j);
      as.J(i, j - 1) = c * ja + s * jb;
      as.J(i, j) = -s * ja + c * jb;
    }
  }
  for (int i = 0; i <= q; ++i) as.R(i, q) = d(i);
  as.index[q] = k;
  as.u[q] = multiplier;
  as.is_active[k] = true;
  as.q = q + 1;
}

// Removes the active entry at `position`. Deleting a column leaves R upper
// Hessenberg from that column on; Givens rotations on rows (j, j+1) of R, and
// the same rotations on columns (j, j+1) of J, restore the triangle while
// keeping Jᵀ N_A = [R; 0].
template <int N, int M>
void DenseQpSolver<N, M>::dropConstraint(ActiveSet& as, int position) {
  const int old_q = as.q;
  as.is_active[as.index[position]] = false;
  for (int i = position; i < old_q - 1; ++i) {
    as.index[i] = as.index[i + 1];
    as.u[i] = as.u[i + 1];
    for (int r = 0; r < old_q; ++r) as.R(r, i) = as.R(r, i + 1);
  }
  const int q = old_q - 1;
  for (int r = 0; r < old_q; ++r) as.R(r, q) = 0.0;
  as.q = q;

  for (int j = position; j < q; ++j) {
    const double a = as.R(j, j);
    const double b = as.R(j + 1, j);
    if (b == 0.0) continue;
    const double h = std::hypot(a, b);
    const double c = a / h;
    const double s = b / h;
    as.R(j, j) = h;
    as.R(j + 1, j) = 0.0;
    for (int col = j + 1; col < q; ++col) {
      const double ra = as.R(j, col);
      const double rb = as.R(j + 1, col);
      as.R(j, col) = c * ra + s * rb;
      as.R(j + 1, col) = -s * ra + c * rb;
    }
    for (int i = 0; i < N; ++i) {
      const double ja = as.J(i, j);
      const double jb = as.J(i, j + 1);
      as.J(i, j) = c * ja + s * jb;
      as.J(i, j + 1) = -s * ja + c * jb;
    }
  }
}

template <int N, int M>
void DenseQpSolver<N, M>::writeSolution(const Constraints& c, const ActiveSet& as, const VecN& x,
                                        Solution& solution) {
  solution.x = x;
  solution.row_multipliers.setZero();
  solution.lower_multipliers.setZero();
  solution.upper_multipliers.setZero();
  for (int i = 0; i < as.q; ++i) {
    const int k = as.index[i];
    // Step lengths keep u >= 0 in exact arithmetic; clip rounding-level
    // negatives so callers can rely on the sign.
    const double u = std::max(0.0, as.u[i]);
    // Active bounds are met exactly (the iterate is within rounding of them):
    // a saturated actuator command then equals its limit bit for bit.
    if (k < M) {
      solution.row_multipliers(k) = u / c.row_norm[k];  // undo the unit-norm scaling
    } else if (k < M + N) {
      solution.lower_multipliers(k - M) = u;
      solution.x(k - M) = c.rhs[k];
    } else {
      solution.upper_multipliers(k - M - N) = u;
      solution.x(k - M - N) = -c.rhs[k];
    }
  }
}

template <int N, int M>
QpStatus DenseQpSolver<N, M>::solve(const Problem& problem, Solution& solution) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  solution = Solution{};
  if (!validate(problem)) return solution.status = QpStatus::kInvalidInput;

  // H = L Lᵀ (lower triangle only). LLT reports a non-positive pivot; tiny
  // positive pivots (numerically singular H) are caught by the ratio test.
  const Eigen::LLT<MatN> llt(problem.H);
  if (llt.info() != Eigen::Success) return solution.status = QpStatus::kInvalidInput;
  const double h_diag_max = problem.H.diagonal().maxCoeff();
  const MatN L = llt.matrixL();
  for (int i = 0; i < N; ++i) {
    if (L(i, i) * L(i, i) < settings_.min_pivot_ratio * h_diag_max) {
      return solution.status = QpStatus::kInvalidInput;
    }
  }

  // Start: empty active set, J = L⁻ᵀ, x = −H⁻¹ g (the unconstrained
  // minimiser, optimal for the empty active set, i.e. dual feasible).
  ActiveSet as;
  as.J = llt.matrixU().solve(MatN::Identity());
  as.R.setZero();
  for (int k = 0; k < K; ++k) as.is_active[k] = false;
  for (int i = 0; i < N; ++i) {
    as.index[i] = -1;
    as.u[i] = 0.0;
  }
  as.q = 0;
  if (!as.J.allFinite()) return solution.status = QpStatus::kInvalidInput;
  VecN x = -(as.J * (as.J.transpose() * problem.g));
  const double dependency_threshold = settings_.dependency_tol * as.J.norm();
  const double dependency_threshold_sq = dependency_threshold * dependency_threshold;

  Constraints c;
  int iterations = 0;
  // Reports the current iterate and active multipliers with `status`. Any
  // non-finite value (reachable only through overflow of extreme data) is
  // reported as invalid input rather than passed on.
  auto stop = [&](QpStatus status) {
    writeSolution(c, as, x, solution);
    solution.iterations = iterations;
    if (status == QpStatus::kInvalidInput || !solution.x.allFinite() ||
        !solution.row_multipliers.allFinite() || !solution.lower_multipliers.allFinite() ||
        !solution.upper_multipliers.allFinite()) {
      solution = Solution{};
      solution.iterations = iterations;
      status = QpStatus::kInvalidInput;
    }
    return solution.status = status;
  };

  // Assemble unit-normal constraints.
  c.normal.setZero();
  for (int k = 0; k < M; ++k) {
    c.enabled[k] = false;
    c.rhs[k] = 0.0;
    c.row_norm[k] = 1.0;
    if (k >= problem.num_rows) continue;
    const double norm = problem.A.row(k).norm();
    if (norm == 0.0) {
      // 0 >= b: vacuous or contradictory, independent of x.
      if (problem.b(k) > violationTol(problem.b(k))) return stop(QpStatus::kInfeasible);
      continue;
    }
    c.normal.col(k) = problem.A.row(k).transpose() / norm;
    c.rhs[k] = problem.b(k) / norm;
    c.row_norm[k] = norm;
    // A denormal-scale row can push b/‖a‖ out of range.
    if (!std::isfinite(c.rhs[k]) || !c.normal.col(k).allFinite()) {
      return solution.status = QpStatus::kInvalidInput;
    }
    c.enabled[k] = true;
  }
  for (int j = 0; j < N; ++j) {
    const int lo = M + j;
    const int up = M + N + j;
    c.normal(j, lo) = 1.0;   //  x_j >=  lower_j
    c.normal(j, up) = -1.0;  // −x_j >= −upper_j
    c.rhs[lo] = problem.lower(j);
    c.rhs[up] = -problem.upper(j);
    c.row_norm[lo] = c.row_norm[up] = 1.0;
    c.enabled[lo] = std::isfinite(problem.lower(j));
    c.enabled[up] = std::isfinite(problem.upper(j));
  }

  for (;;) {
    // Step 1: choose the most violated inactive constraint (unit normals, so
    // the one farthest from x). None left: x is optimal. A NaN x would pass
    // every test here; stop() turns it into kInvalidInput.
    int p = -1;
    double s_p = 0.0;
    for (int k = 0; k < K; ++k) {
      if (!c.enabled[k] || as.is_active[k]) continue;
      const double s = c.normal.col(k).dot(x) - c.rhs[k];
      if (s < -violationTol(c.rhs[k]) && (p < 0 || s < s_p)) {
        p = k;
        s_p = s;
      }
    }
    if (p < 0) return stop(QpStatus::kSolved);

    // Step 2: move towards satisfying constraint p, dropping active
    // constraints whose multipliers would turn negative, until p can be added.
    const VecN n_p = c.normal.col(p);
    double u_p = 0.0;  // multiplier p accumulates along the way
    for (;;) {
      VecN d = as.J.transpose() * n_p;

      // Primal direction z = J₂ d₂ (changes x without disturbing the active
      // constraints) and dual direction r = R⁻¹ d₁ (rate at which the active
      // multipliers must decrease as u_p grows).
      VecN z = VecN::Zero();
      double d2_sq = 0.0;
      for (int j = as.q; j < N; ++j) {
        z += as.J.col(j) * d(j);
        d2_sq += d(j) * d(j);
      }
      double r[N] = {};
      for (int i = as.q - 1; i >= 0; --i) {
        double acc = d(i);
        for (int k = i + 1; k < as.q; ++k) acc -= as.R(i, k) * r[k];
        r[i] = acc / as.R(i, i);
      }

      // Partial (dual) step: largest t keeping every active u_i − t r_i >= 0.
      double t_dual = kInf;
      int drop = -1;
      for (int i = 0; i < as.q; ++i) {
        if (r[i] > 0.0) {
          const double t = std::max(0.0, as.u[i]) / r[i];
          if (t < t_dual) {
            t_dual = t;
            drop = i;
          }
        }
      }
      // Full (primal) step: makes constraint p active. Along z the slack of p
      // grows at rate n_pᵀz = ‖d₂‖². If n_p is (numerically) in the span of
      // the active normals there is no primal direction.
      const bool dependent = d2_sq <= dependency_threshold_sq;
      const double t_primal = dependent ? kInf : -s_p / d2_sq;

      if (t_dual == kInf && t_primal == kInf) {
        // No primal step and no active constraint can give way: p is
        // inconsistent with the active constraints (GI Step 2(c)(i)).
        return stop(QpStatus::kInfeasible);
      }
      if (iterations >= settings_.max_iterations) return stop(QpStatus::kMaxIterations);
      ++iterations;

      if (t_primal <= t_dual) {
        x += t_primal * z;
        for (int i = 0; i < as.q; ++i) as.u[i] -= t_primal * r[i];
        addConstraint(as, p, u_p + t_primal, d);
        break;
      }
      // A NaN step length (data beyond double range) must not reach the
      // partial step below without a constraint to drop.
      if (drop < 0) return stop(QpStatus::kInvalidInput);

      // Partial step: go as far as the blocking multiplier allows, drop that
      // constraint and retry with the same p.
      if (!dependent) x += t_dual * z;
      for (int i = 0; i < as.q; ++i) as.u[i] -= t_dual * r[i];
      u_p += t_dual;
      dropConstraint(as, drop);
      s_p = n_p.dot(x) - c.rhs[p];
      if (!std::isfinite(s_p)) return stop(QpStatus::kInvalidInput);
    }
  }
}

}  // namespace quadfdi
