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
// Random problems use std::mt19937_64 with fixed seeds. The standard
// distributions are implementation-defined, so the exact problems differ
// between standard libraries, but each run on one platform is deterministic.
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
// that solve() does not touch the heap. Eigen's fixed-size types live on the
// stack; this catches regressions such as a std::vector creeping in.
namespace {
std::atomic<long> g_heap_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_heap_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* ptr = std::malloc(size == 0 ? 1 : size)) return ptr;
  throw std::bad_alloc();
}
// Not inlined: GCC's -Wmismatched-new-delete would otherwise see free() on a
// pointer from operator new at the call site.
[[gnu::noinline]] void operator delete(void* ptr) noexcept { std::free(ptr); }
[[gnu::noinline]] void operator delete(void* ptr, std::size_t) noexcept { std::free(ptr); }

namespace quadfdi {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int N>
using Mat = Eigen::Matrix<double, N, N>;

// ---------------------------------------------------------------------------
// Problem data as one list of constraints nᵀx >= c (general rows, then finite
// bounds), shared by the residual checks and the reference.

template <int N, int M>
struct ConstraintList {
  static constexpr int kMax = M + 2 * N;
  Eigen::Matrix<double, kMax, N> n = Eigen::Matrix<double, kMax, N>::Zero();
  Vec<kMax> c = Vec<kMax>::Zero();
  int count = 0;

  void add(const Vec<N>& normal, double rhs) {
    n.row(count) = normal.transpose();
    c(count) = rhs;
    ++count;
  }
};

template <int N, int M>
ConstraintList<N, M> constraintsOf(const QpProblem<N, M>& p) {
  ConstraintList<N, M> list;
  for (int i = 0; i < p.num_rows; ++i) list.add(p.A.row(i).transpose(), p.b(i));
  for (int j = 0; j < N; ++j) {
    if (std::isfinite(p.lower(j))) list.add(Vec<N>::Unit(j), p.lower(j));
    if (std::isfinite(p.upper(j))) list.add(-Vec<N>::Unit(j), -p.upper(j));
  }
  return list;
}

// Violation of nᵀx >= c as a distance in x, relative once |c|/‖n‖ exceeds 1
// (the same scale-aware measure the solver's tolerance uses).
template <int N>
double scaledViolation(const Vec<N>& n, double c, const Vec<N>& x) {
  const double norm = n.norm();
  if (norm == 0.0) return std::max(0.0, c) / std::max(1.0, std::abs(c));
  return std::max(0.0, (c - n.dot(x)) / norm) / std::max(1.0, std::abs(c) / norm);
}

template <int N, int M>
double objective(const QpProblem<N, M>& p, const Vec<N>& x) {
  return 0.5 * x.dot(p.H * x) + p.g.dot(x);
}

// ---------------------------------------------------------------------------
// Brute-force reference. For every subset S of at most N constraints, solve
//   [ H/σ   −N_Sᵀ ] [x]   [−g/σ]
//   [ N_S     0   ] [μ] = [ c_S ]        (unit-normal rows, σ = max|H|, λ = σμ)
// with full-pivot LU; the scaling keeps both blocks O(1) so that LU stays
// accurate when the multipliers are large. The optimum x* lies in the relative
// interior of some face, and the minimiser over that face's affine hull is x*
// itself, so the best objective among the feasible candidates is the optimum
// (filtering by λ >= 0 would select the same point; leaving it out means ties
// between dependent subsets cannot bite). The smallest maximum violation over
// all candidates also decides feasibility: in an infeasible problem every
// point, so every candidate, violates some constraint by at least the
// problem's infeasibility margin.

template <int N>
struct Reference {
  bool feasible = false;
  double least_violation = kInf;
  Vec<N> x = Vec<N>::Zero();
  double objective = kInf;
};

template <int N, int M>
Reference<N> bruteForce(const QpProblem<N, M>& p, double feasibility_tol = 1e-12) {
  // Dynamic types: one LU instantiation for every N keeps compile time down.
  using KktMat = Eigen::MatrixXd;
  using KktVec = Eigen::VectorXd;

  const ConstraintList<N, M> cl = constraintsOf(p);
  Eigen::Matrix<double, ConstraintList<N, M>::kMax, N> unit_n = cl.n;
  Vec<ConstraintList<N, M>::kMax> unit_c = cl.c;
  for (int k = 0; k < cl.count; ++k) {
    const double norm = cl.n.row(k).norm();
    if (norm == 0.0) continue;  // never part of a nonsingular KKT matrix
    unit_n.row(k) /= norm;
    unit_c(k) /= norm;
  }
  const double sigma = p.H.cwiseAbs().maxCoeff();

  Reference<N> ref;
  const std::uint32_t num_masks = std::uint32_t{1} << cl.count;
  for (std::uint32_t mask = 0; mask < num_masks; ++mask) {
    const int size = static_cast<int>(std::bitset<32>(mask).count());
    if (size > N) continue;
    const int dim = N + size;
    KktMat kkt = KktMat::Zero(dim, dim);
    KktVec rhs(dim);
    kkt.topLeftCorner(N, N) = p.H / sigma;
    rhs.head(N) = -p.g / sigma;
    int col = N;
    for (int k = 0; k < cl.count; ++k) {
      if (!(mask & (std::uint32_t{1} << k))) continue;
      kkt.block(0, col, N, 1) = -unit_n.row(k).transpose();
      kkt.block(col, 0, 1, N) = unit_n.row(k);
      rhs(col) = unit_c(k);
      ++col;
    }
    const Eigen::FullPivLU<KktMat> lu(kkt);
    if (!lu.isInvertible()) continue;  // dependent normals: covered by a smaller subset
    const KktVec sol = lu.solve(rhs);
    const Vec<N> x = sol.head(N);
    double worst = 0.0;
    for (int k = 0; k < cl.count; ++k) {
      worst = std::max(worst, scaledViolation<N>(cl.n.row(k).transpose(), cl.c(k), x));
    }
    ref.least_violation = std::min(ref.least_violation, worst);
    if (worst <= feasibility_tol) {
      const double f = objective(p, x);
      if (!ref.feasible || f < ref.objective) {
        ref.feasible = true;
        ref.objective = f;
        ref.x = x;
      }
    }
  }
  return ref;
}

// ---------------------------------------------------------------------------
// KKT residuals of a returned solution.

struct KktResiduals {
  double primal = 0.0;           // scaled violation, see scaledViolation()
  double dual = 0.0;             // most negative multiplier, or a nonzero one that must be 0
  double complementarity = 0.0;  // max |λ_i · slack_i| / (1 + max |λ|), unit-normal scaling
  double stationarity = 0.0;     // ‖Hx + g − Aᵀλ − λ_lo + λ_up‖∞ / (1 + ‖g‖∞ + ‖Hx‖∞)

  void merge(const KktResiduals& o) {
    primal = std::max(primal, o.primal);
    dual = std::max(dual, o.dual);
    complementarity = std::max(complementarity, o.complementarity);
    stationarity = std::max(stationarity, o.stationarity);
  }
};

template <int N, int M>
KktResiduals kktResiduals(const QpProblem<N, M>& p, const QpSolution<N, M>& s) {
  KktResiduals r;
  const Vec<N> hx = p.H * s.x;
  Vec<N> residual = hx + p.g - s.lower_multipliers + s.upper_multipliers;
  auto check = [&r](double multiplier, double slack) {
    r.dual = std::max(r.dual, -multiplier);
    r.complementarity = std::max(r.complementarity, std::abs(multiplier * slack));
  };
  for (int i = 0; i < M; ++i) {
    const double lambda = s.row_multipliers(i);
    if (i >= p.num_rows) {  // not a constraint: multiplier must be exactly zero
      r.dual = std::max(r.dual, std::abs(lambda));
      continue;
    }
    const Vec<N> a = p.A.row(i).transpose();
    const double norm = a.norm();
    r.primal = std::max(r.primal, scaledViolation<N>(a, p.b(i), s.x));
    check(lambda * norm, (a.dot(s.x) - p.b(i)) / norm);  // unit-normal scaling
    residual -= a * lambda;
  }
  for (int j = 0; j < N; ++j) {
    const double lo = s.lower_multipliers(j);
    const double up = s.upper_multipliers(j);
    if (std::isfinite(p.lower(j))) {
      r.primal = std::max(r.primal, scaledViolation<N>(Vec<N>::Unit(j), p.lower(j), s.x));
      check(lo, s.x(j) - p.lower(j));
    } else {
      r.dual = std::max(r.dual, std::abs(lo));
    }
    if (std::isfinite(p.upper(j))) {
      r.primal = std::max(r.primal, scaledViolation<N>(-Vec<N>::Unit(j), -p.upper(j), s.x));
      check(up, p.upper(j) - s.x(j));
    } else {
      r.dual = std::max(r.dual, std::abs(up));
    }
  }
  // Slacks of active constraints are rounding-level relative to the data, so
  // their product with λ is judged relative to the multipliers' size.
  double lambda_max = 0.0;
  for (int i = 0; i < p.num_rows; ++i) lambda_max = std::max(lambda_max, std::abs(s.row_multipliers(i)) * p.A.row(i).norm());
  lambda_max = std::max({lambda_max, s.lower_multipliers.template lpNorm<Eigen::Infinity>(),
                         s.upper_multipliers.template lpNorm<Eigen::Infinity>()});
  r.complementarity /= 1.0 + lambda_max;
  r.stationarity = residual.template lpNorm<Eigen::Infinity>() /
                   (1.0 + p.g.template lpNorm<Eigen::Infinity>() + hx.template lpNorm<Eigen::Infinity>());
  return r;
}

// Tolerances for the KKT checks. The solver's own feasibility tolerance is
// 1e-10; the remaining residuals are rounding-level for these well-scaled
// problems (the observed worst values are printed by each random suite).
constexpr double kPrimalTol = 1e-9;
constexpr double kComplementarityTol = 1e-6;
constexpr double kStationarityTol = 1e-9;

template <int N, int M>
void expectKkt(const QpProblem<N, M>& p, const QpSolution<N, M>& s, KktResiduals* worst = nullptr) {
  const KktResiduals r = kktResiduals(p, s);
  EXPECT_LE(r.primal, kPrimalTol);
  EXPECT_LE(r.dual, 0.0);  // multipliers are returned clipped at exactly zero
  EXPECT_LE(r.complementarity, kComplementarityTol);
  EXPECT_LE(r.stationarity, kStationarityTol);
  if (worst != nullptr) worst->merge(r);
}

// ---------------------------------------------------------------------------
// Random problem generation.

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(engine_); }
  bool chance(double probability) { return uniform(0.0, 1.0) < probability; }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(engine_); }
  template <int R, int C>
  Eigen::Matrix<double, R, C> normalMatrix() {
    Eigen::Matrix<double, R, C> m;
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) m(i, j) = normal();
    return m;
  }

 private:
  std::mt19937_64 engine_;
};

// H = Q diag(λ) Qᵀ, λ log-uniform over `decades` decades, overall scale
// log-uniform in [0.1, 10].
template <int N>
Mat<N> randomSpd(Rng& rng, double decades) {
  const Eigen::HouseholderQR<Mat<N>> qr(rng.normalMatrix<N, N>());
  const Mat<N> q = qr.householderQ();
  const double scale = std::pow(10.0, rng.uniform(-1.0, 1.0));
  Vec<N> eig;
  for (int i = 0; i < N; ++i) eig(i) = scale * std::pow(10.0, rng.uniform(0.0, decades));
  const Mat<N> h = q * eig.asDiagonal() * q.transpose();
  return 0.5 * (h + h.transpose());
}

struct GenOptions {
  double finite_bound_prob = 0.5;  // each bound finite with this probability
  double tight_prob = 0.3;         // a constraint passes exactly through x0
  bool degenerate = false;         // duplicated / opposite / all-tight rows
};

// Random problem feasible at a known point x0 (returned). The unconstrained
// minimiser is pushed away from x0 so that several constraints are active.
// Rows beyond num_rows are filled with NaN: the solver must ignore them.
template <int N, int M>
QpProblem<N, M> randomFeasible(Rng& rng, const GenOptions& opt, Vec<N>* x0_out = nullptr) {
  QpProblem<N, M> p;
  Vec<N> x0;
  for (int j = 0; j < N; ++j) x0(j) = rng.uniform(-1.0, 1.0);
  p.H = randomSpd<N>(rng, 3.0);
  p.g = -p.H * (x0 + 2.0 * rng.normalMatrix<N, 1>());
  p.num_rows = rng.chance(0.2) ? rng.integer(0, M) : M;
  const double tight = opt.degenerate ? 0.8 : opt.tight_prob;
  for (int i = 0; i < M; ++i) {
    if (i >= p.num_rows) {
      p.A.row(i).setConstant(kNaN);
      p.b(i) = kNaN;
      continue;
    }
    const int kind = (opt.degenerate && i > 0) ? rng.integer(0, 2) : 0;
    if (kind == 1) {  // duplicate of the previous row, rescaled
      const double s = std::pow(10.0, rng.uniform(-1.0, 1.0));
      p.A.row(i) = s * p.A.row(i - 1);
      p.b(i) = s * p.b(i - 1);
    } else if (kind == 2) {  // opposite of the previous row: equality if both tight
      const double s = std::pow(10.0, rng.uniform(-1.0, 1.0));
      p.A.row(i) = -s * p.A.row(i - 1);
      const double prev_slack = p.A.row(i - 1).dot(x0) - p.b(i - 1);
      p.b(i) = -s * p.A.row(i - 1).dot(x0) - (rng.chance(tight) ? 0.0 : s * prev_slack);
    } else {
      p.A.row(i) = std::pow(10.0, rng.uniform(-1.0, 1.0)) * rng.normalMatrix<1, N>();
      const double slack = rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0) * p.A.row(i).norm();
      p.b(i) = p.A.row(i).dot(x0) - slack;
    }
  }
  for (int j = 0; j < N; ++j) {
    if (rng.chance(opt.finite_bound_prob)) p.lower(j) = x0(j) - (rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0));
    if (rng.chance(opt.finite_bound_prob)) p.upper(j) = x0(j) + (rng.chance(tight) ? 0.0 : rng.uniform(0.0, 1.0));
    if (std::isfinite(p.lower(j)) && std::isfinite(p.upper(j)) && rng.chance(0.1)) {
      p.lower(j) = p.upper(j) = x0(j);  // fixed variable
    }
  }
  if (x0_out != nullptr) *x0_out = x0;
  return p;
}

// A problem together with a proof of infeasibility: y >= 0 over the
// constraint list of constraintsOf(), with Σ y_i n_i = 0 and Σ y_i c_i > 0,
// so 0 = Σ y_i n_iᵀx >= Σ y_i c_i > 0 for any x, a contradiction.
template <int N, int M>
struct ProblemWithCertificate {
  QpProblem<N, M> problem;
  Vec<M + 2 * N> y = Vec<M + 2 * N>::Zero();
  double delta = 0.0;  // Σ y_i c_i; > 0 proves infeasibility
};

// Starts from a random feasible problem and overwrites its last row with
// a = −Σ μ_i n_i over a random subset of the other constraints (μ > 0) and
// b = delta − Σ μ_i c_i. Then y = (μ, 1) gives Σ y_i c_i = delta: delta > 0 is
// infeasible. delta < 0 leaves a region of size ~|delta| near that subset's
// face which the other constraints may or may not meet. The subset is one
// other row (contradictory halfspaces), bounds only (halfspace disjoint from
// box faces) or a random mix.
template <int N, int M>
ProblemWithCertificate<N, M> randomWithCertificate(Rng& rng, double delta) {
  static_assert(M >= 1, "needs a row to overwrite");
  ProblemWithCertificate<N, M> out;
  GenOptions opt;
  opt.finite_bound_prob = 0.6;
  QpProblem<N, M>& p = out.problem;
  p = randomFeasible<N, M>(rng, opt);
  p.num_rows = M;
  for (int i = 0; i < M; ++i) {
    if (!p.A.row(i).allFinite()) {
      p.A.row(i) = rng.normalMatrix<1, N>();
      p.b(i) = -rng.uniform(0.0, 3.0);
    }
  }
  const int last = M - 1;
  // Pool of constraint-list indices other than the last row; the list puts
  // rows first, so row i is index i and bounds follow from M on.
  int pool[M + 2 * N];
  int pool_size = 0;
  const int style = rng.integer(0, 2);
  if (style == 0 && last > 0) {
    pool[pool_size++] = rng.integer(0, last - 1);
  } else {
    if (style == 1) {  // make the whole box finite so bounds can cut it off
      for (int j = 0; j < N; ++j) {
        if (!std::isfinite(p.lower(j))) p.lower(j) = -rng.uniform(1.0, 2.0);
        if (!std::isfinite(p.upper(j))) p.upper(j) = std::max(p.lower(j), rng.uniform(1.0, 2.0));
      }
    }
    const ConstraintList<N, M> cl = constraintsOf(p);
    for (int k = (style == 1 ? M : 0); k < cl.count; ++k) {
      if (k != last) pool[pool_size++] = k;
    }
    std::shuffle(pool, pool + pool_size, std::mt19937_64(static_cast<std::uint64_t>(rng.integer(0, 1 << 30))));
    pool_size = std::min(pool_size, rng.integer(1, N));
  }
  const ConstraintList<N, M> cl = constraintsOf(p);
  Vec<N> a = Vec<N>::Zero();
  double b = delta;
  for (int s = 0; s < pool_size; ++s) {
    const int k = pool[s];
    const double mu = rng.uniform(0.2, 2.0);
    out.y(k) += mu;
    a -= mu * cl.n.row(k).transpose();
    b -= mu * cl.c(k);
  }
  p.A.row(last) = a.transpose();
  p.b(last) = b;
  out.y(last) = 1.0;
  out.delta = delta;
  return out;
}

// Checks the certificate on the problem data alone.
template <int N, int M>
void expectCertificate(const ProblemWithCertificate<N, M>& pc) {
  const ConstraintList<N, M> cl = constraintsOf(pc.problem);
  Vec<N> combination = Vec<N>::Zero();
  double rhs = 0.0;
  double scale = 0.0;
  for (int k = 0; k < cl.count; ++k) {
    ASSERT_GE(pc.y(k), 0.0);
    combination += pc.y(k) * cl.n.row(k).transpose();
    rhs += pc.y(k) * cl.c(k);
    scale += pc.y(k) * cl.n.row(k).norm();
  }
  EXPECT_LE(combination.norm(), 1e-12 * scale);
  EXPECT_GT(rhs, 0.0);
}

// ---------------------------------------------------------------------------
// Random suites.

struct SuiteStats {
  KktResiduals worst;
  double worst_objective_gap = 0.0;  // |f − f_ref| / (1 + |½xᵀHx| + |gᵀx|)
  double worst_x_gap = 0.0;          // ‖x − x_ref‖∞ / (1 + ‖x_ref‖∞)
  int max_iterations = 0;
  int referenced = 0;

  void print(const std::string& name, int count) const {
    std::cout << "[ stats    ] " << name << ": " << count << " problems (" << referenced
              << " vs brute force), worst primal " << worst.primal << ", complementarity "
              << worst.complementarity << ", stationarity " << worst.stationarity << ", objective gap "
              << worst_objective_gap << ", x gap " << worst_x_gap << ", max iterations " << max_iterations
              << "\n";
  }
};

template <int N, int M>
void expectMatchesReference(const QpProblem<N, M>& p, const QpSolution<N, M>& s, const Reference<N>& ref,
                            SuiteStats* stats) {
  ASSERT_TRUE(ref.feasible);
  // Relative to the objective's terms, not its value, which may cancel.
  const double f = objective(p, s.x);
  const double f_scale = 1.0 + 0.5 * std::abs(ref.x.dot(p.H * ref.x)) + std::abs(p.g.dot(ref.x));
  const double objective_gap = std::abs(f - ref.objective) / f_scale;
  const double x_gap = (s.x - ref.x).template lpNorm<Eigen::Infinity>() /
                       (1.0 + ref.x.template lpNorm<Eigen::Infinity>());
  EXPECT_LE(objective_gap, 1e-6);
  EXPECT_LE(x_gap, 1e-6);
  stats->worst_objective_gap = std::max(stats->worst_objective_gap, objective_gap);
  stats->worst_x_gap = std::max(stats->worst_x_gap, x_gap);
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
    // Optimality over the known feasible point as a cheap sanity check.
    EXPECT_LE(objective(p, s.x), objective(p, x0) + 1e-9 * (1.0 + std::abs(objective(p, x0))));
    stats.max_iterations = std::max(stats.max_iterations, s.iterations);
    if (k < reference_count) expectMatchesReference(p, s, bruteForce(p), &stats);
    if (::testing::Test::HasFailure()) break;  // first failing problem is enough
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
    const auto pc = randomWithCertificate<N, M>(rng, std::pow(10.0, rng.uniform(-5.0, 0.0)));
    expectCertificate(pc);
    QpSolution<N, M> s;
    EXPECT_EQ(solver.solve(pc.problem, s), QpStatus::kInfeasible);
    EXPECT_TRUE(s.x.allFinite());
    max_iterations = std::max(max_iterations, s.iterations);
    if (k < reference_count) {
      EXPECT_FALSE(bruteForce(pc.problem).feasible);
    }
    if (::testing::Test::HasFailure()) break;
  }
  std::cout << "[ stats    ] " << name << ": " << count << " infeasible problems (" << reference_count
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
    const double magnitude = std::pow(10.0, rng.uniform(-6.0, 0.0));
    const double delta = rng.chance(0.5) ? magnitude : -magnitude;
    const auto pc = randomWithCertificate<N, M>(rng, delta);
    const Reference<N> ref = bruteForce(pc.problem);
    QpSolution<N, M> s;
    const QpStatus status = solver.solve(pc.problem, s);
    if (delta > 0.0) {
      expectCertificate(pc);
      EXPECT_GT(ref.least_violation, 1e-12);  // reference agrees with the certificate
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
    const long before = g_heap_allocations.load();
    const QpStatus a = solver.solve(feasible, s);
    const QpStatus b = solver.solve(infeasible.problem, s);
    const long after = g_heap_allocations.load();
    ASSERT_EQ(a, QpStatus::kSolved);
    ASSERT_EQ(b, QpStatus::kInfeasible);
    ASSERT_EQ(after, before);
  }
  // The counter itself works.
  const long before = g_heap_allocations.load();
  auto* probe = new int(3);
  EXPECT_GT(g_heap_allocations.load(), before);
  delete probe;
}

// ---------------------------------------------------------------------------
// Random suites. Counts are sized so the whole binary runs in a few seconds.

TEST(QpSolverRandom, FeasibleN4M2) {
  runFeasibleSuite<4, 2>("N=4 M=2", 101, 10000, 2000, GenOptions{});
}
TEST(QpSolverRandom, FeasibleN4M4) {
  runFeasibleSuite<4, 4>("N=4 M=4", 102, 10000, 2000, GenOptions{});
}
TEST(QpSolverRandom, FeasibleN2M2) {
  runFeasibleSuite<2, 2>("N=2 M=2", 103, 3000, 3000, GenOptions{});
}
TEST(QpSolverRandom, FeasibleN3M4) {
  runFeasibleSuite<3, 4>("N=3 M=4", 104, 3000, 2000, GenOptions{});
}
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
TEST(QpSolverRandom, TinyOrEmptyN4M4) { runTinyOrEmptySuite<4, 4>("tiny/empty N=4 M=4", 402, 1000); }
TEST(QpSolverRandom, TinyOrEmptyN2M4) { runTinyOrEmptySuite<2, 4>("tiny/empty N=2 M=4", 403, 2000); }
TEST(QpSolverRandom, TinyOrEmptyN3M4) { runTinyOrEmptySuite<3, 4>("tiny/empty N=3 M=4", 404, 1000); }

}  // namespace
}  // namespace quadfdi
