// Tests for the Goldfarb-Idnani QP solver (src/control/qp_solver.h).
//
// Besides hand-worked problems, every random problem is checked twice:
//   * against the KKT conditions, which hold at the optimum of a convex QP and
//     only there (H is positive definite, so the optimum is unique);
//   * against an independent brute-force reference that enumerates candidate
//     active sets and solves each equality-constrained KKT system with Eigen's
//     full-pivot LU; it shares no code with the solver.
// Infeasible problems are built together with a Farkas certificate
// (y >= 0, Σ y_i n_i = 0, Σ y_i c_i > 0), which the tests verify on the data,
// so "infeasible" is proved, not assumed.
//
// Random problems come from std::mt19937_64 with fixed seeds (see Rng).
#include "control/qp_solver.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <bitset>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <new>
#include <random>
#include <string>

// Counts every global operator new in this test binary, so a test can assert
// that solve() does not touch the heap (a std::vector creeping in, say).
#include "heap_counter.h"  // include once per test executable

namespace quadfdi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;

using Eigen::MatrixXd;
using Eigen::VectorXd;

// ---------------------------------------------------------------------------
// The test-side helpers (residuals, reference, certificates) work on this
// dynamic-size copy of a problem: written once instead of per (N, M), which
// also keeps this file's compile time reasonable. Every constraint becomes one
// row nᵀx >= c: the general rows first, then the finite bounds.

struct DenseQp {
  MatrixXd H;
  VectorXd g;
  MatrixXd n;  // constraint normals, one per row
  VectorXd c;
};

template <int N, int M>
DenseQp denseOf(const QpProblem<N, M>& p) {
  DenseQp q;
  q.H = p.H;
  q.g = p.g;
  int count = p.num_rows;
  for (int j = 0; j < N; ++j) count += int{std::isfinite(p.lower(j))} + int{std::isfinite(p.upper(j))};
  q.n = MatrixXd::Zero(count, N);
  q.c = VectorXd::Zero(count);
  int k = 0;
  for (int i = 0; i < p.num_rows; ++i, ++k) {
    q.n.row(k) = p.A.row(i);
    q.c(k) = p.b(i);
  }
  for (int j = 0; j < N; ++j) {
    if (std::isfinite(p.lower(j))) {
      q.n(k, j) = 1.0;
      q.c(k++) = p.lower(j);
    }
    if (std::isfinite(p.upper(j))) {
      q.n(k, j) = -1.0;
      q.c(k++) = -p.upper(j);
    }
  }
  return q;
}

// The solution's multipliers in DenseQp order.
template <int N, int M>
VectorXd multipliersOf(const QpProblem<N, M>& p, const QpSolution<N, M>& s) {
  VectorXd lambda(denseOf(p).c.size());
  int k = 0;
  for (int i = 0; i < p.num_rows; ++i) lambda(k++) = s.row_multipliers(i);
  for (int j = 0; j < N; ++j) {
    if (std::isfinite(p.lower(j))) lambda(k++) = s.lower_multipliers(j);
    if (std::isfinite(p.upper(j))) lambda(k++) = s.upper_multipliers(j);
  }
  return lambda;
}

// Multipliers of things that are not constraints (rows past num_rows,
// infinite bounds) must be exactly zero.
template <int N, int M>
double strayMultipliers(const QpProblem<N, M>& p, const QpSolution<N, M>& s) {
  double stray = 0.0;
  for (int i = p.num_rows; i < M; ++i) stray = std::max(stray, std::abs(s.row_multipliers(i)));
  for (int j = 0; j < N; ++j) {
    if (!std::isfinite(p.lower(j))) stray = std::max(stray, std::abs(s.lower_multipliers(j)));
    if (!std::isfinite(p.upper(j))) stray = std::max(stray, std::abs(s.upper_multipliers(j)));
  }
  return stray;
}

// Violation of nᵀx >= c as a distance in x, relative once |c|/‖n‖ exceeds 1:
// the same scale-aware measure as the solver's feasibility_tol.
double scaledViolation(const VectorXd& n, double c, const VectorXd& x) {
  const double norm = n.norm();
  if (norm == 0.0) return std::max(0.0, c) / std::max(1.0, std::abs(c));
  return std::max(0.0, (c - n.dot(x)) / norm) / std::max(1.0, std::abs(c) / norm);
}

double maxViolation(const DenseQp& q, const VectorXd& x) {
  double worst = 0.0;
  for (int k = 0; k < q.c.size(); ++k) {
    worst = std::max(worst, scaledViolation(q.n.row(k).transpose(), q.c(k), x));
  }
  return worst;
}

double objective(const DenseQp& q, const VectorXd& x) { return 0.5 * x.dot(q.H * x) + q.g.dot(x); }

// ---------------------------------------------------------------------------
// Brute-force reference. For every subset S of at most N constraints, solve
//   [ H/σ   −D N_Sᵀ ] [x]   [ −g/σ  ]
//   [ D N_S     0   ] [μ] = [ D c_S ]      (λ_S = σ D μ)
// with full-pivot LU and iterative refinement on an extended-precision
// residual. σ ≈ max|H| and D ≈ diag(1/‖n_k‖) are powers of two, so the scaled
// system is exactly the problem's, both blocks are O(1), and the refined
// candidate is accurate to working precision even when the system is very
// ill-conditioned (near-degenerate random problems reach condition numbers
// around 1e12). A candidate is a KKT point, hence THE optimum of the strictly
// convex problem, iff it is feasible and μ >= 0; the optimum has such a
// candidate (its active constraints contain a linearly independent subset
// carrying the multipliers). In floating point, candidates are accepted within
// a loose tolerance and the one that meets it best is kept; choosing the
// lowest objective instead would favour slightly infeasible candidates. The
// smallest maximum violation over all candidates decides feasibility: in an
// infeasible problem every point, so every candidate, violates some
// constraint by at least the infeasibility margin.

struct Reference {
  bool found = false;             // a KKT candidate within the tolerance exists
  double least_violation = kInf;  // over all candidates; ~0 iff feasible
  VectorXd x;
  VectorXd lambda;  // multipliers of the chosen candidate, DenseQp order
  double objective = kInf;
  double kkt_error = kInf;  // max(violation, relative negativity of μ)
  double sigma_min = 1.0;   // smallest singular value of its unit normals
};

// The power of two nearest below v > 0: scaling by it is exact.
double powerOfTwoBelow(double v) {
  int exponent = 0;
  std::frexp(v, &exponent);
  return std::ldexp(1.0, exponent - 1);
}

Reference bruteForce(const DenseQp& q, double kkt_tol = 1e-6) {
  const int n = static_cast<int>(q.g.size());
  const int count = static_cast<int>(q.c.size());
  MatrixXd scaled_n = q.n;
  VectorXd scaled_c = q.c;
  VectorXd scale(count);
  for (int k = 0; k < count; ++k) {
    const double norm = q.n.row(k).norm();
    scale(k) = norm == 0.0 ? 1.0 : 1.0 / powerOfTwoBelow(norm);  // zero rows never form a nonsingular system
    scaled_n.row(k) *= scale(k);
    scaled_c(k) *= scale(k);
  }
  const double sigma = powerOfTwoBelow(q.H.cwiseAbs().maxCoeff());

  Reference ref;
  std::uint32_t best_mask = 0;
  const std::uint32_t num_masks = std::uint32_t{1} << count;
  for (std::uint32_t mask = 0; mask < num_masks; ++mask) {
    const int size = static_cast<int>(std::bitset<32>(mask).count());
    if (size > n) continue;
    MatrixXd kkt = MatrixXd::Zero(n + size, n + size);
    VectorXd rhs(n + size);
    kkt.topLeftCorner(n, n) = q.H / sigma;
    rhs.head(n) = -q.g / sigma;
    int col = n;
    for (int k = 0; k < count; ++k) {
      if (!(mask & (std::uint32_t{1} << k))) continue;
      kkt.block(0, col, n, 1) = -scaled_n.row(k).transpose();
      kkt.block(col, 0, 1, n) = scaled_n.row(k);
      rhs(col) = scaled_c(k);
      ++col;
    }
    const Eigen::FullPivLU<MatrixXd> lu(kkt);
    if (!lu.isInvertible()) continue;  // dependent normals: covered by a smaller subset
    VectorXd sol = lu.solve(rhs);
    for (int refinement = 0; refinement < 2; ++refinement) {
      VectorXd residual(n + size);
      for (int i = 0; i < n + size; ++i) {
        auto acc = static_cast<long double>(rhs(i));
        for (int j = 0; j < n + size; ++j) {
          acc -= static_cast<long double>(kkt(i, j)) * static_cast<long double>(sol(j));
        }
        residual(i) = static_cast<double>(acc);
      }
      sol += lu.solve(residual);
    }
    const VectorXd x = sol.head(n);
    const double violation = maxViolation(q, x);
    ref.least_violation = std::min(ref.least_violation, violation);
    double kkt_error = violation;
    if (size > 0) {
      const VectorXd mu = sol.tail(size);
      kkt_error = std::max(kkt_error, -mu.minCoeff() / (1.0 + mu.lpNorm<Eigen::Infinity>()));
    }
    if (kkt_error <= kkt_tol && kkt_error < ref.kkt_error) {
      ref.found = true;
      ref.kkt_error = kkt_error;
      ref.x = x;
      ref.objective = objective(q, x);
      ref.lambda = VectorXd::Zero(count);
      for (int k = 0, j = n; k < count; ++k) {
        if (mask & (std::uint32_t{1} << k)) ref.lambda(k) = sigma * scale(k) * sol(j++);
      }
      best_mask = mask;
    }
  }
  const int size = static_cast<int>(std::bitset<32>(best_mask).count());
  if (ref.found && size > 0) {
    MatrixXd active(n, size);
    for (int k = 0, j = 0; k < count; ++k) {
      if (best_mask & (std::uint32_t{1} << k)) active.col(j++) = q.n.row(k).normalized().transpose();
    }
    ref.sigma_min = Eigen::JacobiSVD<MatrixXd>(active).singularValues()(size - 1);
  }
  return ref;
}

// ---------------------------------------------------------------------------
// KKT residuals of a returned solution.

struct KktResiduals {
  double primal = 0.0;           // max scaled violation, see scaledViolation()
  double dual = 0.0;             // most negative multiplier, or a stray nonzero one
  double complementarity = 0.0;  // max |λ_i · slack_i| / (1 + max |λ|), unit-normal scaling
  double stationarity = 0.0;  // ‖Hx + g − Σ λ_i n_i‖∞ / (1 + ‖g‖∞ + ‖Hx‖∞ + ‖Σ |λ_i n_i|‖∞)

  void merge(const KktResiduals& o) {
    primal = std::max(primal, o.primal);
    dual = std::max(dual, o.dual);
    complementarity = std::max(complementarity, o.complementarity);
    stationarity = std::max(stationarity, o.stationarity);
  }
};

// For the bounds, Σ λ_i n_i is exactly +λ_lower − λ_upper, so the stationarity
// here is the one of the interface: H x + g − Aᵀλ − λ_lower + λ_upper = 0.
KktResiduals kktResiduals(const DenseQp& q, const VectorXd& x, const VectorXd& lambda) {
  KktResiduals r;
  const VectorXd hx = q.H * x;
  const VectorXd residual = hx + q.g - q.n.transpose() * lambda;
  double lambda_max = 0.0;
  for (int k = 0; k < q.c.size(); ++k) {
    const double norm = q.n.row(k).norm();
    const double unit_lambda = lambda(k) * norm;  // multiplier of the unit-normal row
    const double unit_slack = (q.n.row(k).dot(x) - q.c(k)) / norm;
    r.primal = std::max(r.primal, scaledViolation(q.n.row(k).transpose(), q.c(k), x));
    r.dual = std::max(r.dual, -lambda(k));
    // Slacks of active constraints are rounding-level relative to the data,
    // so their product with λ is judged relative to the multipliers' size.
    r.complementarity = std::max(r.complementarity, std::abs(unit_lambda * unit_slack));
    lambda_max = std::max(lambda_max, std::abs(unit_lambda));
  }
  r.complementarity /= 1.0 + lambda_max;
  // Relative to the size of the terms being summed: with huge multipliers
  // (near-degenerate problems) Σ λ_k n_k cancels to the size of g.
  const VectorXd constraint_terms = q.n.cwiseAbs().transpose() * lambda.cwiseAbs();
  r.stationarity = residual.lpNorm<Eigen::Infinity>() /
                   (1.0 + q.g.lpNorm<Eigen::Infinity>() + hx.lpNorm<Eigen::Infinity>() +
                    constraint_terms.lpNorm<Eigen::Infinity>());
  return r;
}

// Tolerances for the KKT checks. Primal and complementarity: the solver's
// contract (feasibility_tol, same measure; an active constraint is met to
// within it). Stationarity is pure rounding. The worst values observed, printed
// by each random suite, are orders of magnitude below these; over ~4.5e6
// problems from 150 other seeds they were: primal 2.3e-11, complementarity
// 1.5e-12, stationarity 1.9e-14.
constexpr double kPrimalTol = 1e-10;
constexpr double kComplementarityTol = 1e-10;
constexpr double kStationarityTol = 1e-12;

template <int N, int M>
void expectKkt(const QpProblem<N, M>& p, const QpSolution<N, M>& s, KktResiduals* worst = nullptr) {
  KktResiduals r = kktResiduals(denseOf(p), s.x, multipliersOf(p, s));
  r.dual = std::max(r.dual, strayMultipliers(p, s));
  EXPECT_LE(r.primal, kPrimalTol);
  EXPECT_LE(r.dual, 0.0);  // multipliers are returned clipped at exactly zero
  EXPECT_LE(r.complementarity, kComplementarityTol);
  EXPECT_LE(r.stationarity, kStationarityTol);
  if (worst != nullptr) worst->merge(r);
}

// ---------------------------------------------------------------------------
// Random problem generation.

// Draws are built from the engine's raw output, which the standard fixes
// (unlike the std:: distributions), so the problems are the same with every
// standard library, up to libm rounding in log/cos/pow.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  double normal() {  // Box-Muller
    const double radius = std::sqrt(-2.0 * std::log(1.0 - unit()));
    return radius * std::cos(2.0 * kPi * unit());
  }
  bool chance(double probability) { return unit() < probability; }
  int integer(int lo, int hi) {  // inclusive; the modulo bias is irrelevant here
    return lo + static_cast<int>(engine_() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  double logUniform(double lo_exp, double hi_exp) { return std::pow(10.0, uniform(lo_exp, hi_exp)); }
  MatrixXd normalMatrix(int rows, int cols) {
    MatrixXd m(rows, cols);
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) m(i, j) = normal();
    }
    return m;
  }

 private:
  static constexpr double kPi = 3.14159265358979323846;
  std::mt19937_64 engine_;
};

// H = Q diag(λ) Qᵀ, λ log-uniform over `decades` decades, overall scale
// log-uniform in [0.1, 10].
MatrixXd randomSpd(Rng& rng, int n, double decades) {
  const MatrixXd q = Eigen::HouseholderQR<MatrixXd>(rng.normalMatrix(n, n)).householderQ();
  const double scale = rng.logUniform(-1.0, 1.0);
  VectorXd eig(n);
  for (int i = 0; i < n; ++i) eig(i) = scale * rng.logUniform(0.0, decades);
  const MatrixXd h = q * eig.asDiagonal() * q.transpose();
  return 0.5 * (h + h.transpose());
}

struct GenOptions {
  double finite_bound_prob = 0.5;  // each bound finite with this probability
  double tight_prob = 0.3;         // a constraint passes exactly through x0
  bool degenerate = false;         // duplicated / opposite / mostly tight rows
};

// Random problem feasible at a known point x0 (returned). The unconstrained
// minimiser is pushed away from x0 so that several constraints are active.
// Rows beyond num_rows are filled with NaN: the solver must ignore them.
template <int N, int M>
QpProblem<N, M> randomFeasible(Rng& rng, const GenOptions& opt, Vec<N>* x0_out = nullptr) {
  QpProblem<N, M> p;
  Vec<N> x0;
  for (int j = 0; j < N; ++j) x0(j) = rng.uniform(-1.0, 1.0);
  p.H = randomSpd(rng, N, 3.0);
  const Vec<N> target = x0 + 2.0 * Vec<N>(rng.normalMatrix(N, 1));
  p.g = -p.H * target;
  p.num_rows = rng.chance(0.2) ? rng.integer(0, M) : M;
  const double tight = opt.degenerate ? 0.8 : opt.tight_prob;
  for (int i = 0; i < M; ++i) {
    if (i >= p.num_rows) {
      p.A.row(i).setConstant(kNaN);
      p.b(i) = kNaN;
      continue;
    }
    const int kind = (opt.degenerate && i > 0) ? rng.integer(0, 2) : 0;
    const double scale = rng.logUniform(-1.0, 1.0);
    if (kind == 1) {  // duplicate of the previous row, rescaled
      p.A.row(i) = scale * p.A.row(i - 1);
      p.b(i) = scale * p.b(i - 1);
    } else if (kind == 2) {  // opposite of the previous row: an equality if both are tight
      const double prev_slack = p.A.row(i - 1).dot(x0) - p.b(i - 1);
      p.A.row(i) = -scale * p.A.row(i - 1);
      p.b(i) = p.A.row(i).dot(x0) - (rng.chance(tight) ? 0.0 : scale * prev_slack);
    } else {
      p.A.row(i) = scale * rng.normalMatrix(1, N);
      const double slack = rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0) * p.A.row(i).norm();
      p.b(i) = p.A.row(i).dot(x0) - slack;
    }
  }
  for (int j = 0; j < N; ++j) {
    if (rng.chance(opt.finite_bound_prob)) {
      p.lower(j) = x0(j) - (rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0));
    }
    if (rng.chance(opt.finite_bound_prob)) {
      p.upper(j) = x0(j) + (rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0));
    }
    if (std::isfinite(p.lower(j)) && std::isfinite(p.upper(j)) && rng.chance(0.1)) {
      p.lower(j) = p.upper(j) = x0(j);  // fixed variable
    }
  }
  if (x0_out != nullptr) *x0_out = x0;
  return p;
}

// A problem with a proof of infeasibility when delta > 0: y >= 0 over the
// DenseQp constraint order with Σ y_k n_k = 0 and Σ y_k c_k = delta, so that
// 0 = Σ y_k n_kᵀx >= Σ y_k c_k = delta holds for no x.
template <int N, int M>
struct ProblemWithCertificate {
  QpProblem<N, M> problem;
  VectorXd y;
  double delta = 0.0;
};

// Starts from a random feasible problem and overwrites its last row with
// a = −Σ μ_k n_k over a random subset of the other constraints (μ > 0) and
// b = delta − Σ μ_k c_k; y = (μ, 1) is then the certificate. With delta < 0
// the last row leaves a region of size ~|delta| next to that subset's face,
// which the other constraints may or may not meet. The subset is one other
// row (contradictory halfspaces), bounds only (halfspace disjoint from faces
// of the box) or a random mix.
template <int N, int M>
ProblemWithCertificate<N, M> randomWithCertificate(Rng& rng, double delta) {
  static_assert(M >= 2, "needs a row to overwrite and one to contradict");
  ProblemWithCertificate<N, M> out;
  GenOptions opt;
  opt.finite_bound_prob = 0.6;
  QpProblem<N, M>& p = out.problem;
  p = randomFeasible<N, M>(rng, opt);
  p.num_rows = M;
  for (int i = 0; i < M; ++i) {
    if (!p.A.row(i).allFinite()) {
      p.A.row(i) = rng.normalMatrix(1, N);
      p.b(i) = -rng.uniform(0.0, 3.0);
    }
  }
  const int style = rng.integer(0, 2);
  if (style == 1) {  // the whole box finite, so that bounds alone can cut it off
    for (int j = 0; j < N; ++j) {
      if (!std::isfinite(p.lower(j))) p.lower(j) = -rng.uniform(1.0, 2.0);
      if (!std::isfinite(p.upper(j))) p.upper(j) = std::max(p.lower(j), rng.uniform(1.0, 2.0));
    }
  }
  // DenseQp order: rows 0..M−1 first (the last one is being replaced), then
  // the finite bounds.
  const DenseQp q = denseOf(p);
  const int last = M - 1;
  const int count = static_cast<int>(q.c.size());
  int pool[M + 2 * N];
  int pool_size = 0;
  if (style == 0) {
    pool[pool_size++] = rng.integer(0, last - 1);
  } else {
    for (int k = (style == 1 ? M : 0); k < count; ++k) {
      if (k != last) pool[pool_size++] = k;
    }
    for (int i = pool_size - 1; i > 0; --i) std::swap(pool[i], pool[rng.integer(0, i)]);
    pool_size = std::min(pool_size, rng.integer(1, N));
  }
  out.y = VectorXd::Zero(count);
  VectorXd a = VectorXd::Zero(N);
  double b = delta;
  for (int s = 0; s < pool_size; ++s) {
    const int k = pool[s];
    const double mu = rng.uniform(0.2, 2.0);
    out.y(k) += mu;
    a -= mu * q.n.row(k).transpose();
    b -= mu * q.c(k);
  }
  p.A.row(last) = a.transpose();
  p.b(last) = b;
  out.y(last) = 1.0;
  out.delta = delta;
  return out;
}

// Checks the certificate on the final problem data alone.
template <int N, int M>
void expectCertificate(const ProblemWithCertificate<N, M>& pc) {
  const DenseQp q = denseOf(pc.problem);
  ASSERT_EQ(q.c.size(), pc.y.size());
  ASSERT_GE(pc.y.minCoeff(), 0.0);
  double scale = 0.0;
  for (int k = 0; k < q.c.size(); ++k) scale += pc.y(k) * q.n.row(k).norm();
  EXPECT_LE((q.n.transpose() * pc.y).norm(), 1e-12 * scale);
  EXPECT_GT(q.c.dot(pc.y), 0.0);
}

// ---------------------------------------------------------------------------
// Random suites.

struct SuiteStats {
  KktResiduals worst;
  double worst_objective_gap = 0.0;  // |f − f_ref| / (1 + |½xᵀHx| + |gᵀx|)
  double worst_x_gap = 0.0;          // ‖x − x_ref‖∞ / (1 + ‖x_ref‖∞)
  double worst_scaled_x_gap = 0.0;   // the same times σ_min² (see expectMatchesReference())
  int max_iterations = 0;
  int referenced = 0;

  void print(const std::string& name, int count) const {
    std::cout << "[ stats    ] " << name << ": " << count << " solved (" << referenced
              << " vs brute force), worst primal " << worst.primal << ", complementarity "
              << worst.complementarity << ", stationarity " << worst.stationarity << ", objective gap "
              << worst_objective_gap << ", x gap " << worst_x_gap
              << " (times sigma_min^2: " << worst_scaled_x_gap << "), max iterations " << max_iterations
              << "\n";
  }
};

// Rounding-level bound on f(x) − f(y) for a KKT pair (x, λ) and a feasible
// y. By convexity f(x) − f(y) <= ∇f(x)ᵀ(x − y) = λᵀ(s(x) − s(y)) + rᵀ(x − y),
// with s the slacks n_kᵀ· − c_k and r = Hx + g − Σ λ_k n_k. At an exact
// optimum (λ >= 0, λ_k s_k(x) = 0, r = 0) and an exactly feasible y (s(y) >= 0)
// the right-hand side is <= 0; in floating point it is bounded by the terms
// below, which matter only when the multipliers are huge, as they are in
// near-degenerate random problems (up to ~1e7).
double roundingAllowance(const DenseQp& q, const VectorXd& x, const VectorXd& lambda, const VectorXd& y) {
  // A slack cannot be evaluated more accurately than this, and multiplied by
  // a huge λ even that is visible in the objective.
  constexpr double kEps = 16.0 * std::numeric_limits<double>::epsilon();
  const VectorXd r = q.H * x + q.g - q.n.transpose() * lambda;
  double sum = std::abs(r.dot(x - y));
  for (int k = 0; k < q.c.size(); ++k) {
    const double slack_x = q.n.row(k).dot(x) - q.c(k);
    const double slack_y = q.n.row(k).dot(y) - q.c(k);
    const double noise =
        kEps * (q.n.row(k).cwiseAbs().dot(x.cwiseAbs() + y.cwiseAbs()) + 2.0 * std::abs(q.c(k)));
    sum += std::abs(lambda(k)) * (std::abs(slack_x) + std::max(0.0, -slack_y) + noise);
  }
  return sum;
}

double objectiveScale(const DenseQp& q, const VectorXd& x) {
  return 1.0 + 0.5 * std::abs(x.dot(q.H * x)) + std::abs(q.g.dot(x));
}

template <int N, int M>
void expectMatchesReference(const QpProblem<N, M>& p, const QpSolution<N, M>& s, const Reference& ref,
                            SuiteStats* stats) {
  ASSERT_TRUE(ref.found);
  const DenseQp q = denseOf(p);
  const VectorXd lambda = multipliersOf(p, s);
  // Objective compared relative to its terms, not its value, which may
  // cancel, and in both directions up to rounding (see roundingAllowance()).
  const double f_scale = objectiveScale(q, ref.x);
  const double f_s = objective(q, s.x);
  EXPECT_LE(f_s - ref.objective, 1e-12 * f_scale + roundingAllowance(q, s.x, lambda, ref.x));
  EXPECT_LE(ref.objective - f_s, 1e-12 * f_scale + roundingAllowance(q, ref.x, ref.lambda, s.x));
  // x is as well determined as the active normals are independent: nearly
  // parallel ones (σ_min → 0) amplify rounding by up to 1/σ_min². Over ~1.7e6
  // comparisons from 150 other seeds, x_gap · σ_min² stayed below 6e-14.
  const double x_gap =
      (s.x - ref.x).template lpNorm<Eigen::Infinity>() / (1.0 + ref.x.lpNorm<Eigen::Infinity>());
  EXPECT_LE(x_gap, 1e-12 / (ref.sigma_min * ref.sigma_min));
  stats->worst_objective_gap = std::max(stats->worst_objective_gap, std::abs(f_s - ref.objective) / f_scale);
  stats->worst_x_gap = std::max(stats->worst_x_gap, x_gap);
  stats->worst_scaled_x_gap = std::max(stats->worst_scaled_x_gap, x_gap * ref.sigma_min * ref.sigma_min);
  ++stats->referenced;
}

// `count` random feasible problems, all KKT-checked; the first
// `reference_count` also against the brute-force reference.
template <int N, int M>
void runFeasibleSuite(const std::string& name, std::uint64_t seed, int count, int reference_count,
                      const GenOptions& opt) {
  Rng rng(seed);
  const DenseQpSolver<N, M> solver;
  SuiteStats stats;
  for (int k = 0; k < count; ++k) {
    SCOPED_TRACE(name + " problem " + std::to_string(k));
    Vec<N> x0;
    const QpProblem<N, M> p = randomFeasible<N, M>(rng, opt, &x0);
    QpSolution<N, M> s;
    ASSERT_EQ(solver.solve(p, s), QpStatus::kSolved);
    EXPECT_EQ(s.status, QpStatus::kSolved);
    expectKkt(p, s, &stats.worst);
    // Cheap independent check: no worse than the known feasible point, up to
    // rounding (see roundingAllowance()).
    const DenseQp q = denseOf(p);
    const VectorXd x0_dynamic = x0;
    EXPECT_LE(
        objective(q, s.x) - objective(q, x0_dynamic),
        1e-12 * objectiveScale(q, x0_dynamic) + roundingAllowance(q, s.x, multipliersOf(p, s), x0_dynamic));
    stats.max_iterations = std::max(stats.max_iterations, s.iterations);
    if (k < reference_count) expectMatchesReference(p, s, bruteForce(q), &stats);
    if (::testing::Test::HasFailure()) break;  // the first failing problem is enough
  }
  stats.print(name, count);
}

template <int N, int M>
void runInfeasibleSuite(const std::string& name, std::uint64_t seed, int count, int reference_count) {
  Rng rng(seed);
  const DenseQpSolver<N, M> solver;
  int max_iterations = 0;
  for (int k = 0; k < count; ++k) {
    SCOPED_TRACE(name + " problem " + std::to_string(k));
    const auto pc = randomWithCertificate<N, M>(rng, rng.logUniform(-5.0, 0.0));
    expectCertificate(pc);
    QpSolution<N, M> s;
    EXPECT_EQ(solver.solve(pc.problem, s), QpStatus::kInfeasible);
    EXPECT_TRUE(s.x.allFinite());
    max_iterations = std::max(max_iterations, s.iterations);
    if (k < reference_count) {
      EXPECT_GT(bruteForce(denseOf(pc.problem)).least_violation, 1e-9);
    }
    if (::testing::Test::HasFailure()) break;
  }
  std::cout << "[ stats    ] " << name << ": " << count << " infeasible (" << reference_count
            << " vs brute force), max iterations " << max_iterations << "\n";
}

// Problems whose feasible region is tiny (size ~|delta|) or empty, decided by
// the brute-force reference; the solver must agree. Cases in the band where
// the reference's least violation lies between the two tolerances are too
// close to call and are skipped (and counted).
template <int N, int M>
void runTinyOrEmptySuite(const std::string& name, std::uint64_t seed, int count) {
  Rng rng(seed);
  const DenseQpSolver<N, M> solver;
  SuiteStats stats;
  int feasible = 0;
  int infeasible = 0;
  int skipped = 0;
  for (int k = 0; k < count; ++k) {
    SCOPED_TRACE(name + " problem " + std::to_string(k));
    const double magnitude = rng.logUniform(-6.0, 0.0);
    const double delta = rng.chance(0.5) ? magnitude : -magnitude;
    const auto pc = randomWithCertificate<N, M>(rng, delta);
    const Reference ref = bruteForce(denseOf(pc.problem));
    QpSolution<N, M> s;
    const QpStatus status = solver.solve(pc.problem, s);
    stats.max_iterations = std::max(stats.max_iterations, s.iterations);
    if (delta > 0.0) {
      expectCertificate(pc);
      EXPECT_GT(ref.least_violation, 1e-12);  // the reference agrees with the certificate
    }
    if (ref.least_violation <= 1e-12) {
      ++feasible;
      ASSERT_EQ(status, QpStatus::kSolved);
      expectKkt(pc.problem, s, &stats.worst);
      expectMatchesReference(pc.problem, s, ref, &stats);
    } else if (ref.least_violation >= 1e-7) {
      ++infeasible;
      EXPECT_EQ(status, QpStatus::kInfeasible);
    } else {
      ++skipped;
    }
    if (::testing::Test::HasFailure()) break;
  }
  std::cout << "[ stats    ] " << name << ": " << feasible << " feasible, " << infeasible << " infeasible, "
            << skipped << " too close to call\n";
  stats.print(name, feasible);
  EXPECT_GE(feasible, count / 10);
  EXPECT_GE(infeasible, count / 10);
  EXPECT_LE(skipped, count / 20);
}

// ---------------------------------------------------------------------------
// Hand-worked problems.

using Solver2 = DenseQpSolver<2, 2>;
using Problem2 = QpProblem<2, 2>;
using Solution2 = QpSolution<2, 2>;

// ½(2x₁² + 4x₂²) − 2x₁ − 8x₂: unconstrained minimiser (1, 2).
Problem2 simpleProblem() {
  Problem2 p;
  p.H << 2.0, 0.0, 0.0, 4.0;
  p.g << -2.0, -8.0;
  p.num_rows = 0;
  return p;
}

// ½‖x − point‖², i.e. Euclidean projection of `point`.
Problem2 projectionProblem(double px, double py) {
  Problem2 p;
  p.H.setIdentity();
  p.g << -px, -py;
  p.num_rows = 0;
  return p;
}

TEST(QpSolver, StatusToString) {
  EXPECT_STREQ(toString(QpStatus::kSolved), "solved");
  EXPECT_STREQ(toString(QpStatus::kInfeasible), "infeasible");
  EXPECT_STREQ(toString(QpStatus::kMaxIterations), "max_iterations");
  EXPECT_STREQ(toString(QpStatus::kInvalidInput), "invalid_input");
}

TEST(QpSolver, Unconstrained) {
  const Problem2 p = simpleProblem();
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 2.0, 1e-14);
  EXPECT_EQ(s.iterations, 0);
  EXPECT_TRUE(s.row_multipliers.isZero());
  EXPECT_TRUE(s.lower_multipliers.isZero());
  EXPECT_TRUE(s.upper_multipliers.isZero());
}

TEST(QpSolver, InactiveConstraintsChangeNothing) {
  Problem2 p = simpleProblem();
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;  // x₁ + x₂ >= 0, satisfied at (1, 2)
  p.b(0) = 0.0;
  p.lower << 0.0, 0.0;
  p.upper << 5.0, 5.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 2.0, 1e-14);
  expectKkt(p, s);
}

// x₁ <= 0.5 active: x = (0.5, 2); stationarity (2·0.5 − 2) + λ_up = 0 → λ_up = 1.
TEST(QpSolver, OneActiveUpperBound) {
  Problem2 p = simpleProblem();
  p.upper(0) = 0.5;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.5, 1e-14);
  EXPECT_NEAR(s.x(1), 2.0, 1e-14);
  EXPECT_NEAR(s.upper_multipliers(0), 1.0, 1e-14);
  EXPECT_EQ(s.upper_multipliers(1), 0.0);
  EXPECT_TRUE(s.lower_multipliers.isZero());
  EXPECT_EQ(s.iterations, 1);
  expectKkt(p, s);
}

// x₂ >= 3 active: x = (1, 3); 4·3 − 8 − λ_lo = 0 → λ_lo = 4.
TEST(QpSolver, OneActiveLowerBound) {
  Problem2 p = simpleProblem();
  p.lower(1) = 3.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 3.0, 1e-14);
  EXPECT_NEAR(s.lower_multipliers(1), 4.0, 1e-13);
  expectKkt(p, s);
}

// Projection of the origin onto {x₁ + x₂ >= 1.5} ∩ [0, 1]²: the halfspace
// projection (0.75, 0.75) is inside the box; x = λ a → λ = 0.75.
TEST(QpSolver, ProjectionOntoHalfspaceInsideBox) {
  Problem2 p = projectionProblem(0.0, 0.0);
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 1.5;
  p.lower << 0.0, 0.0;
  p.upper << 1.0, 1.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.75, 1e-14);
  EXPECT_NEAR(s.x(1), 0.75, 1e-14);
  EXPECT_NEAR(s.row_multipliers(0), 0.75, 1e-14);
  expectKkt(p, s);
}

// Projection of (2, −1) onto the same set: x = (1, 0.5) with the row and the
// upper bound of x₁ active. x − p = (−1, 1.5) = λ(1, 1) − λ_up e₁ → λ = 1.5,
// λ_up = 2.5. The unconstrained start (2, −1) violates three constraints, and
// the method must drop x₂ >= 0 on the way.
TEST(QpSolver, ProjectionOntoBoxAndHalfspace) {
  Problem2 p = projectionProblem(2.0, -1.0);
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 1.5;
  p.lower << 0.0, 0.0;
  p.upper << 1.0, 1.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 0.5, 1e-14);
  EXPECT_NEAR(s.row_multipliers(0), 1.5, 1e-14);
  EXPECT_NEAR(s.upper_multipliers(0), 2.5, 1e-14);
  EXPECT_EQ(s.lower_multipliers(1), 0.0);
  expectKkt(p, s);
}

// Row scaling must not change x, and multipliers scale inversely.
TEST(QpSolver, RowScalingInvariance) {
  for (const double scale : {1e-6, 1.0, 1e6}) {
    Problem2 p = projectionProblem(2.0, -1.0);
    p.num_rows = 1;
    p.A.row(0) << scale, scale;
    p.b(0) = 1.5 * scale;
    p.lower << 0.0, 0.0;
    p.upper << 1.0, 1.0;
    Solution2 s;
    ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved) << scale;
    EXPECT_NEAR(s.x(0), 1.0, 1e-12);
    EXPECT_NEAR(s.x(1), 0.5, 1e-12);
    EXPECT_NEAR(s.row_multipliers(0) * scale, 1.5, 1e-12);
    expectKkt(p, s);
  }
}

// A 4-thrust problem shaped like the CBF-QP safety filter: track a nominal
// thrust f_nom = (0.2, 0.1, 0.1, 0.1) under 0 <= f <= 0.15 and one row capping
// the total, minimise ½‖f − f_nom‖². KKT gives f_i = clip(f_nom,i − λ).
TEST(QpSolver, ThrustAllocationShape) {
  using Solver4 = DenseQpSolver<4, 2>;
  QpProblem<4, 2> p;
  p.H.setIdentity();
  p.g << -0.2, -0.1, -0.1, -0.1;
  p.num_rows = 1;
  p.A.row(0) << -1.0, -1.0, -1.0, -1.0;
  p.b(0) = -0.5;
  p.lower.setConstant(0.0);
  p.upper.setConstant(0.15);
  QpSolution<4, 2> s;
  ASSERT_EQ(Solver4().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.15, 1e-14);
  EXPECT_NEAR(s.x(1), 0.1, 1e-14);
  EXPECT_NEAR(s.upper_multipliers(0), 0.05, 1e-14);
  EXPECT_EQ(s.row_multipliers(0), 0.0);
  expectKkt(p, s);

  // Cap the total at 0.3: with λ <= 0.05, f₁ = 0.15 and 0.15 + 3(0.1 − λ) = 0.3
  // gives λ = 0.05, where f₁ = 0.2 − λ sits exactly on its bound (degenerate:
  // bound active with zero multiplier).
  p.b(0) = -0.3;
  ASSERT_EQ(Solver4().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.15, 1e-14);
  EXPECT_NEAR(s.x(1), 0.05, 1e-14);
  EXPECT_NEAR(s.x(2), 0.05, 1e-14);
  EXPECT_NEAR(s.x(3), 0.05, 1e-14);
  EXPECT_NEAR(s.x.sum(), 0.3, 1e-14);
  expectKkt(p, s);
}

// ---------------------------------------------------------------------------
// Infeasibility.

TEST(QpSolver, HalfspaceDisjointFromBox) {
  Problem2 p = simpleProblem();
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 2.5;  // box [0,1]² has x₁ + x₂ <= 2
  p.lower << 0.0, 0.0;
  p.upper << 1.0, 1.0;
  Solution2 s;
  EXPECT_EQ(Solver2().solve(p, s), QpStatus::kInfeasible);
  EXPECT_EQ(s.status, QpStatus::kInfeasible);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(QpSolver, ContradictoryHalfspaces) {
  Problem2 p = simpleProblem();
  p.num_rows = 2;
  p.A.row(0) << 1.0, -2.0;  //  x₁ − 2x₂ >= 1
  p.b(0) = 1.0;
  p.A.row(1) << -3.0, 6.0;  // −3x₁ + 6x₂ >= −3 + 1e-6, i.e. x₁ − 2x₂ <= 1 − 3.3e-7
  p.b(1) = -3.0 + 1e-6;
  Solution2 s;
  EXPECT_EQ(Solver2().solve(p, s), QpStatus::kInfeasible);
}

TEST(QpSolver, ZeroRow) {
  Problem2 p = simpleProblem();
  p.num_rows = 1;
  p.A.row(0).setZero();
  p.b(0) = -1.0;  // 0 >= −1: vacuous
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(1), 2.0, 1e-14);
  EXPECT_EQ(s.row_multipliers(0), 0.0);
  p.b(0) = 1.0;  // 0 >= 1: impossible
  EXPECT_EQ(Solver2().solve(p, s), QpStatus::kInfeasible);
}

// ---------------------------------------------------------------------------
// Degenerate cases.

// Minimise ½‖x‖² s.t. x₁ + x₂ >= 1 and −x₁ − x₂ >= −1 (an equality).
TEST(QpSolver, EqualityFromTwoOppositeRows) {
  Problem2 p = projectionProblem(0.0, 0.0);
  p.num_rows = 2;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 1.0;
  p.A.row(1) << -1.0, -1.0;
  p.b(1) = -1.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.5, 1e-14);
  EXPECT_NEAR(s.x(1), 0.5, 1e-14);
  EXPECT_NEAR(s.row_multipliers(0) - s.row_multipliers(1), 0.5, 1e-14);
  expectKkt(p, s);

  // Pull from the other side: now the second row carries the multiplier.
  p.g << -3.0, -3.0;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.5, 1e-14);
  EXPECT_NEAR(s.row_multipliers(1) - s.row_multipliers(0), 2.5, 1e-14);
  expectKkt(p, s);
}

TEST(QpSolver, DuplicatedRows) {
  Problem2 p = projectionProblem(0.0, 0.0);
  p.num_rows = 2;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 1.0;
  p.A.row(1) << 2.0, 2.0;  // same halfspace, other scale
  p.b(1) = 2.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.5, 1e-14);
  EXPECT_NEAR(s.x(1), 0.5, 1e-14);
  // x = A₀ᵀλ₀ + A₁ᵀλ₁ → λ₀ + 2λ₁ = 0.5, split arbitrary.
  EXPECT_NEAR(s.row_multipliers(0) + 2.0 * s.row_multipliers(1), 0.5, 1e-14);
  expectKkt(p, s);
}

// Three constraints active at the solution (1, 1) in two dimensions.
TEST(QpSolver, RedundantConstraintsActiveAtSolution) {
  Problem2 p = projectionProblem(0.0, 0.0);
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 2.0;
  p.lower << 1.0, 1.0;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 1.0, 1e-14);
  expectKkt(p, s);

  // Same vertex, reached from a start where the bounds are violated most.
  p = projectionProblem(-3.0, 0.5);
  p.num_rows = 1;
  p.A.row(0) << 1.0, 1.0;
  p.b(0) = 2.0;
  p.lower << 1.0, 1.0;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_NEAR(s.x(1), 1.0, 1e-14);
  expectKkt(p, s);
}

TEST(QpSolver, FixedVariable) {
  Problem2 p = simpleProblem();
  p.lower(1) = p.upper(1) = 0.3;
  Solution2 s;
  ASSERT_EQ(Solver2().solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 1.0, 1e-14);
  EXPECT_EQ(s.x(1), 0.3);
  // 4·0.3 − 8 = −6.8 = λ_lo − λ_up
  EXPECT_NEAR(s.upper_multipliers(1) - s.lower_multipliers(1), 6.8, 1e-13);
  expectKkt(p, s);
}

TEST(QpSolver, NoRowsWithMaximalRowCapacity) {
  QpProblem<4, 4> p;
  p.H = Vec<4>(1.0, 2.0, 3.0, 4.0).asDiagonal();
  p.g << -1.0, -1.0, -1.0, -1.0;
  p.num_rows = 0;
  p.A.setConstant(kNaN);  // unused rows are never read
  p.b.setConstant(kNaN);
  p.upper.setConstant(0.4);
  QpSolution<4, 4> s;
  const DenseQpSolver<4, 4> solver;
  ASSERT_EQ(solver.solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.4, 1e-14);
  EXPECT_NEAR(s.x(1), 0.4, 1e-14);
  EXPECT_NEAR(s.x(2), 1.0 / 3.0, 1e-14);
  EXPECT_NEAR(s.x(3), 0.25, 1e-14);
  EXPECT_TRUE(s.row_multipliers.isZero());
  expectKkt(p, s);
}

TEST(QpSolver, MaxIterationsStopsWithFiniteIterate) {
  Problem2 p = projectionProblem(5.0, 5.0);
  p.upper << 1.0, 1.0;  // needs two additions
  QpSettings settings;
  settings.max_iterations = 1;
  Solution2 s;
  EXPECT_EQ(Solver2(settings).solve(p, s), QpStatus::kMaxIterations);
  EXPECT_EQ(s.iterations, 1);
  EXPECT_TRUE(s.x.allFinite());
  settings.max_iterations = 2;
  EXPECT_EQ(Solver2(settings).solve(p, s), QpStatus::kSolved);
  EXPECT_EQ(s.iterations, 2);
}

// ---------------------------------------------------------------------------
// Invalid input.

TEST(QpSolver, InvalidInput) {
  const Solver2 solver;
  Problem2 base = projectionProblem(0.5, 0.5);
  base.num_rows = 1;
  base.A.row(0) << 1.0, 1.0;
  base.b(0) = 0.0;
  base.lower << -1.0, -1.0;
  base.upper << 1.0, 1.0;
  Solution2 s;
  ASSERT_EQ(solver.solve(base, s), QpStatus::kSolved);

  auto expectInvalid = [&solver](const Problem2& p, const char* what) {
    Solution2 sol;
    sol.x.setConstant(7.0);
    EXPECT_EQ(solver.solve(p, sol), QpStatus::kInvalidInput) << what;
    EXPECT_EQ(sol.status, QpStatus::kInvalidInput) << what;
    EXPECT_TRUE(sol.x.isZero()) << what;  // nothing stale or non-finite leaks out
  };
  Problem2 p = base;
  p.H(0, 0) = kNaN;
  expectInvalid(p, "NaN in H");
  p = base;
  p.H(1, 0) = p.H(0, 1) = kInf;
  expectInvalid(p, "inf in H");
  p = base;
  p.g(1) = kNaN;
  expectInvalid(p, "NaN in g");
  p = base;
  p.A(0, 1) = kNaN;
  expectInvalid(p, "NaN in A");
  p = base;
  p.b(0) = kInf;
  expectInvalid(p, "inf in b");
  p = base;
  p.b(0) = -kInf;
  expectInvalid(p, "-inf in b");
  p = base;
  p.lower(0) = kNaN;
  expectInvalid(p, "NaN lower");
  p = base;
  p.upper(1) = kNaN;
  expectInvalid(p, "NaN upper");
  p = base;
  p.lower(0) = kInf;
  p.upper(0) = kInf;
  expectInvalid(p, "+inf lower");
  p = base;
  p.lower(0) = -kInf;
  p.upper(0) = -kInf;
  expectInvalid(p, "-inf upper");
  p = base;
  p.lower(1) = 1.0 + 1e-12;
  expectInvalid(p, "lower > upper");
  p = base;
  p.H << 1.0, 0.0, 0.0, -1.0;
  expectInvalid(p, "indefinite H");
  p = base;
  p.H << 1.0, 1.0, 1.0, 1.0;
  expectInvalid(p, "singular H");
  p = base;
  p.H << 1.0, 0.0, 0.0, 1e-15;
  expectInvalid(p, "numerically singular H");
  p = base;
  p.H.setZero();
  expectInvalid(p, "zero H");
  p = base;
  p.H << 2.0, 1.0, 0.0, 2.0;
  expectInvalid(p, "asymmetric H");
  p = base;
  p.num_rows = -1;
  expectInvalid(p, "num_rows < 0");
  p = base;
  p.num_rows = 3;
  expectInvalid(p, "num_rows > M");
  expectInvalid(Problem2{}, "default-constructed problem (H = 0)");

  // Data past num_rows is not part of the problem and must not be checked.
  p = base;
  p.A.row(1).setConstant(kNaN);
  p.b(1) = kNaN;
  EXPECT_EQ(solver.solve(p, s), QpStatus::kSolved);
  // A well-conditioned but badly scaled H is valid.
  p = base;
  p.H *= 1e-8;
  p.g *= 1e-8;
  ASSERT_EQ(solver.solve(p, s), QpStatus::kSolved);
  EXPECT_NEAR(s.x(0), 0.5, 1e-12);
}

// Extreme but finite data must end in a status, never in NaN output.
TEST(QpSolver, OverflowIsReportedNotPropagated) {
  Problem2 p = projectionProblem(0.0, 0.0);
  p.H *= 1e-300;
  p.g << -1e300, 1e300;  // x = −H⁻¹g overflows
  Solution2 s;
  const QpStatus status = Solver2().solve(p, s);
  EXPECT_EQ(status, QpStatus::kInvalidInput);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(QpSolver, SolveDoesNotAllocate) {
  Rng rng(7);
  const DenseQpSolver<4, 4> solver;
  GenOptions opt;
  QpSolution<4, 4> s;
  for (int k = 0; k < 200; ++k) {
    const QpProblem<4, 4> feasible = randomFeasible<4, 4>(rng, opt);
    const auto infeasible = randomWithCertificate<4, 4>(rng, 0.1);
    const long before = quadfdi::test::heap_allocations.load();
    const QpStatus a = solver.solve(feasible, s);
    const QpStatus b = solver.solve(infeasible.problem, s);
    const long after = quadfdi::test::heap_allocations.load();
    ASSERT_EQ(a, QpStatus::kSolved);
    ASSERT_EQ(b, QpStatus::kInfeasible);
    ASSERT_EQ(after, before);
  }
  // The counter itself works. A direct call, because a new-expression whose
  // result is unused may be elided.
  const long before = quadfdi::test::heap_allocations.load();
  void* probe = ::operator new(16);
  EXPECT_GT(quadfdi::test::heap_allocations.load(), before);
  ::operator delete(probe);
}

// ---------------------------------------------------------------------------
// Random suites. Counts are sized so the whole binary runs in a few seconds.

TEST(QpSolverRandom, FeasibleN4M2) { runFeasibleSuite<4, 2>("N=4 M=2", 101, 10000, 2000, GenOptions{}); }
TEST(QpSolverRandom, FeasibleN4M4) { runFeasibleSuite<4, 4>("N=4 M=4", 102, 10000, 1500, GenOptions{}); }
TEST(QpSolverRandom, FeasibleN2M2) { runFeasibleSuite<2, 2>("N=2 M=2", 103, 3000, 3000, GenOptions{}); }
TEST(QpSolverRandom, FeasibleN3M4) { runFeasibleSuite<3, 4>("N=3 M=4", 104, 3000, 2000, GenOptions{}); }
TEST(QpSolverRandom, FeasibleN6M4) {
  GenOptions opt;
  opt.finite_bound_prob = 0.3;  // keeps the reference's subset count small
  runFeasibleSuite<6, 4>("N=6 M=4", 105, 3000, 300, opt);
}
TEST(QpSolverRandom, DegenerateN4M4) {
  GenOptions opt;
  opt.degenerate = true;
  runFeasibleSuite<4, 4>("degenerate N=4 M=4", 201, 5000, 1500, opt);
}
TEST(QpSolverRandom, DegenerateN2M4) {
  GenOptions opt;
  opt.degenerate = true;
  opt.finite_bound_prob = 0.7;
  runFeasibleSuite<2, 4>("degenerate N=2 M=4", 202, 3000, 3000, opt);
}
TEST(QpSolverRandom, DegenerateN3M4) {
  GenOptions opt;
  opt.degenerate = true;
  runFeasibleSuite<3, 4>("degenerate N=3 M=4", 203, 3000, 1500, opt);
}
TEST(QpSolverRandom, InfeasibleN4M2) { runInfeasibleSuite<4, 2>("N=4 M=2", 301, 3000, 500); }
TEST(QpSolverRandom, InfeasibleN4M4) { runInfeasibleSuite<4, 4>("N=4 M=4", 302, 3000, 500); }
TEST(QpSolverRandom, InfeasibleN2M2) { runInfeasibleSuite<2, 2>("N=2 M=2", 303, 2000, 2000); }
TEST(QpSolverRandom, InfeasibleN3M4) { runInfeasibleSuite<3, 4>("N=3 M=4", 304, 2000, 500); }
TEST(QpSolverRandom, InfeasibleN6M4) { runInfeasibleSuite<6, 4>("N=6 M=4", 305, 1000, 0); }
TEST(QpSolverRandom, TinyOrEmptyN4M2) { runTinyOrEmptySuite<4, 2>("tiny/empty N=4 M=2", 401, 1000); }
TEST(QpSolverRandom, TinyOrEmptyN4M4) { runTinyOrEmptySuite<4, 4>("tiny/empty N=4 M=4", 402, 700); }
TEST(QpSolverRandom, TinyOrEmptyN2M4) { runTinyOrEmptySuite<2, 4>("tiny/empty N=2 M=4", 403, 2000); }
TEST(QpSolverRandom, TinyOrEmptyN3M4) { runTinyOrEmptySuite<3, 4>("tiny/empty N=3 M=4", 404, 1000); }

}  // namespace
}  // namespace quadfdi
