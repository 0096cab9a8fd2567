// ceres_shim.cpp — thin extern "C" layer over Ceres' C++ Solver API for sparse linear
// least-squares stages (toolchain.md: the C API exposes no solver options and prints reports).
//
// Solver choice, deliberately: the problem is LINEAR (fixed knots, fixed sample parameters,
// gluing functions taken from the construction), so a single Gauss-Newton step from any start is
// the exact least-squares solution.  Levenberg-Marquardt with an initial trust-region radius of
// 1e16 makes its damping (diag/radius) negligible, so one iteration (max_num_iterations = 1) is
// that step.  A stage holds many independent blocks (one per mesh edge or per patch).  Dense
// path (the default): each block is its own problem, blocks spread over worker threads; a block of
// at most TINY_BLOCK unknowns (nearly all) goes to Ceres' TinySolver (one LM step, per coordinate),
// a larger one to ceres::Solve with DENSE_QR (Eigen), whose cost is mostly per Solve and per
// residual/parameter block, so such a block is ONE residual block (BlockCost: its rows as a dense
// matrix, which is also the Jacobian) over ONE parameter block (its unknowns), one coordinate at a
// time, reusing the Problem for the three Solves.  Sparse path: batches of blocks
// in one SPARSE_NORMAL_CHOLESKY (SuiteSparse CHOLMOD) Solve each (solve_batched: one dense
// residual block per block and coordinate; 11x faster than one residual block per row, which
// remains for problems given without blocks); num_threads parallelises its Jacobian evaluation.
// Logging is silent, since library code never prints.
#include "core/ceres_shim.h"

#include <ceres/ceres.h>
#include <ceres/tiny_solver.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace {

// One row  r = sum_j c_j x_j - b  with parameter blocks of size dim (1: one coordinate of
// each unknown; 3: the whole point, Jacobian blocks c_j I_3).
class RowCost : public ceres::CostFunction {
public:
    RowCost(const double *c, int k, const double *b, int dim) : c_(c, c + k), dim_(dim)
    {
        for (int d = 0; d < dim; d++) b_[d] = b[d];
        set_num_residuals(dim);
        for (int j = 0; j < k; j++) mutable_parameter_block_sizes()->push_back(dim);
    }
    bool Evaluate(double const *const *p, double *r, double **J) const override
    {
        for (int d = 0; d < dim_; d++) r[d] = -b_[d];
        for (size_t j = 0; j < c_.size(); j++)
            for (int d = 0; d < dim_; d++) r[d] += c_[j] * p[j][d];
        if (J)
            for (size_t j = 0; j < c_.size(); j++) {
                if (!J[j]) continue;
                for (int e = 0; e < dim_ * dim_; e++) J[j][e] = 0.0;
                for (int d = 0; d < dim_; d++) J[j][d * dim_ + d] = c_[j];
            }
        return true;
    }

private:
    std::vector<double> c_;
    double b_[3];
    int dim_;
};

// One whole block as a single residual block over a single parameter block: the block's rows as
// a dense row-major m x n matrix A (unknowns numbered from the block's first one).  dim 1:
// one coordinate, p = that coordinate of the n unknowns, r = A p - b.  dim 3: p = the n
// unknowns as 3-vectors (x, y, z interleaved, as in the caller's x), r = (A (x) I_3) p - b with
// b the rows' 3-vector right-hand sides (same interleaving).  The object is reused from block
// to block (the Problem does not own it): set() resizes it before each new Problem.
class BlockCost : public ceres::CostFunction {
public:
    void set(int m, int n, int dim, const double *A, const double *b)
    {
        m_ = m;
        n_ = n;
        dim_ = dim;
        A_ = A;
        b_ = b;
        set_num_residuals(m * dim);
        mutable_parameter_block_sizes()->assign(1, n * dim);
    }
    bool Evaluate(double const *const *p, double *r, double **J) const override
    {
        const double *q = p[0];
        if (dim_ == 1) {
            for (int i = 0; i < m_; i++) {
                const double *a = A_ + (size_t)i * n_;
                double t = -b_[i];
                for (int j = 0; j < n_; j++) t += a[j] * q[j];
                r[i] = t;
            }
            if (J && J[0]) std::memcpy(J[0], A_, (size_t)m_ * n_ * sizeof(double));
            return true;
        }
        for (int i = 0; i < m_; i++) {
            const double *a = A_ + (size_t)i * n_;
            double t0 = -b_[3 * i], t1 = -b_[3 * i + 1], t2 = -b_[3 * i + 2];
            for (int j = 0; j < n_; j++) {
                t0 += a[j] * q[3 * j];
                t1 += a[j] * q[3 * j + 1];
                t2 += a[j] * q[3 * j + 2];
            }
            r[3 * i] = t0;
            r[3 * i + 1] = t1;
            r[3 * i + 2] = t2;
        }
        if (J && J[0]) {
            // row 3i+d, column 3j+e of a (3m) x (3n) row-major matrix: A[i][j] if d == e
            double *Jm = J[0];
            const size_t w = (size_t)3 * n_;
            std::memset(Jm, 0, (size_t)3 * m_ * w * sizeof(double));
            for (int i = 0; i < m_; i++)
                for (int j = 0; j < n_; j++) {
                    double a = A_[(size_t)i * n_ + j];
                    for (int d = 0; d < 3; d++) Jm[(3 * (size_t)i + d) * w + 3 * (size_t)j + d] = a;
                }
        }
        return true;
    }

private:
    const double *A_ = nullptr, *b_ = nullptr;
    int m_ = 0, n_ = 0, dim_ = 1;
};

/* Blocks whose rows do not gather into one dense matrix (solve_rows: one residual block per row)
 * with at most this many unknowns are solved as 3-vectors in one Ceres problem (3m x 3n Jacobian,
 * 27x the QR flops of one coordinate); larger ones per coordinate.  Measured per Solve here (Ceres
 * 2.1, Eigen DENSE_QR): a fixed ~4.3 us plus the QR; 3-vectors win up to n = 5 (m = 26: 19 us vs
 * 3 x 6.8 us), tie at n = 6 and lose beyond (n = 8, m = 30: 32 us vs 3 x 7.9 us). */
enum { SMALL_BLOCK = 5 };

/* Blocks with at most this many unknowns go to Ceres' TinySolver (ceres/tiny_solver.h: Ceres'
 * Levenberg-Marquardt for small dense problems, normal equations and LDLT, no Problem to build), one
 * coordinate at a time; larger ones to ceres::Solve (DENSE_QR).  Why: a fit solves tens of thousands
 * of such blocks (a 732-face mesh with many extraordinary vertices: 53 000, 99.7 % with at most 16
 * unknowns) and ceres::Solve's fixed cost per call (problem, program, evaluator and solver set up
 * anew, ~10-20 us) was most of the solve stage; B-spline least-squares blocks that small are well
 * conditioned, so normal equations lose nothing the tolerance could see. */
enum { TINY_BLOCK = 16 };

/* One block and coordinate for TinySolver: r = A p - b, A row-major m x n (the Jacobian, which
 * TinySolver wants column-major). */
struct TinyCost {
    typedef double Scalar;
    enum { NUM_RESIDUALS = Eigen::Dynamic, NUM_PARAMETERS = Eigen::Dynamic };
    const double *A = nullptr, *b = nullptr;
    int m = 0, n = 0;
    int NumResiduals() const { return m; }
    int NumParameters() const { return n; }
    bool operator()(const double *p, double *r, double *J) const
    {
        for (int i = 0; i < m; i++) {
            const double *a = A + (size_t)i * n;
            double s = -b[i];
            for (int j = 0; j < n; j++) s += a[j] * p[j];
            r[i] = s;
        }
        if (J)
            for (int j = 0; j < n; j++)
                for (int i = 0; i < m; i++) J[(size_t)j * m + i] = A[(size_t)i * n + j];
        return true;
    }
};

/* One worker's reusable state for the dense per-block path. */
struct BlockWorker {
    ceres::Context *ctx = nullptr;
    ceres::Solver::Options opt;
    ceres::Problem::Options popt;
    BlockCost cost;
    std::vector<double> A, b, bd, p;
    std::vector<int> used;
    /* small blocks: the solver keeps its matrices between blocks of one shape (TinySolver resizes
     * only when the shape changes) */
    ceres::TinySolver<TinyCost> tiny;
    Eigen::VectorXd tp;
    BlockWorker()
    {
        ctx = ceres::Context::Create();
        popt.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
        popt.context = ctx;
        /* one Gauss-Newton step from the current values (the problem is linear): no damping to
         * speak of, no tolerance that could skip the step; an infinite function tolerance ends the
         * solve as soon as the step is accepted, before TinySolver re-evaluates the Jacobian and
         * J^T J at the new point for a next iteration there is none of (x is the same bits: that
         * evaluation only fed the summary, which is not read) */
        tiny.options.max_num_iterations = 2;
        tiny.options.initial_trust_region_radius = 1e16;
        tiny.options.gradient_tolerance = 0;
        tiny.options.parameter_tolerance = 0;
        tiny.options.function_tolerance = std::numeric_limits<double>::infinity();
        tiny.options.cost_threshold = 0;
    }
    ~BlockWorker() { delete ctx; }
    BlockWorker(const BlockWorker &) = delete;
    BlockWorker &operator=(const BlockWorker &) = delete;
};

}  // namespace

/* Gather the block's rows into w.A (dense, row-major m x n; repeated entries add up) and its
 * right-hand sides into w.b (row r's 3-vector at 3r).  Returns 0 if some entry lies outside the
 * block's unknowns or some unknown appears in no row (then the caller uses solve_rows, which
 * leaves such an unknown alone). */
static int gather_block(BlockWorker &w, int r0, int r1, int v0, int v1, const int *row_start, const int *col,
                        const double *val, const double *rhs)
{
    const int m = r1 - r0, n = v1 - v0;
    w.A.assign((size_t)m * n, 0.0);
    w.used.assign((size_t)n, 0);
    for (int i = 0; i < m; i++) {
        double *a = w.A.data() + (size_t)i * n;
        for (int e = row_start[r0 + i]; e < row_start[r0 + i + 1]; e++) {
            int j = col[e] - v0;
            if (j < 0 || j >= n) return 0;
            a[j] += val[e];
            w.used[(size_t)j] = 1;
        }
    }
    for (int j = 0; j < n; j++)
        if (!w.used[(size_t)j]) return 0;
    w.b.assign(rhs + 3 * (size_t)r0, rhs + 3 * (size_t)r1);
    return 1;
}

static void set_solver_options(ceres::Solver::Options &o, int threads, int dense)
{
    o.minimizer_type = ceres::TRUST_REGION;
    o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    o.initial_trust_region_radius = 1e16;
    o.max_trust_region_radius = 1e16;
    o.max_num_iterations = 1;
    o.linear_solver_type = dense ? ceres::DENSE_QR : ceres::SPARSE_NORMAL_CHOLESKY;
    o.num_threads = threads > 0 ? threads : 1;
    o.logging_type = ceres::SILENT;
    o.minimizer_progress_to_stdout = false;
}

/* One Solve; 0 on success, else 1 with Ceres' message. */
static int run_solve(const ceres::Solver::Options &o, ceres::Problem &problem, char *msg, int msglen)
{
    ceres::Solver::Summary s;
    ceres::Solve(o, &problem, &s);
    if (!s.IsSolutionUsable() || s.num_successful_steps < 1) {
        std::snprintf(msg, (size_t)msglen, "ceres: %s", s.message.c_str());
        return 1;
    }
    return 0;
}

/* One Ceres solve of rows [r0, r1) (variables anywhere in x), one residual block per row and
 * one parameter block per unknown: coordinate d alone (dim 1) or all three coordinates as
 * 3-vectors (dim 3, d = 0). */
static int solve_rows(int r0, int r1, int d, int dim, const int *row_start, const int *col, const double *val,
                      const double *rhs, double *x, const ceres::Solver::Options &o, char *msg, int msglen)
{
    ceres::Problem problem;
    std::vector<double *> blocks;
    int used = 0;
    for (int r = r0; r < r1; r++) {
        int k = row_start[r + 1] - row_start[r];
        if (k == 0) continue;
        blocks.clear();
        for (int e = row_start[r]; e < row_start[r + 1]; e++) blocks.push_back(x + 3 * col[e] + d);
        problem.AddResidualBlock(new RowCost(val + row_start[r], k, rhs + 3 * r + d, dim), nullptr, blocks);
        used++;
    }
    if (!used) return 0;
    return run_solve(o, problem, msg, msglen);
}

/* Block [r0, r1) x [v0, v1) as dense Ceres problems (see BlockCost); falls back to solve_rows
 * (one residual block per row, one parameter block per unknown) when the block's entries do
 * not fit gather_block's layout. */
static int solve_block(BlockWorker &w, int r0, int r1, int v0, int v1, const int *row_start, const int *col,
                       const double *val, const double *rhs, double *x, char *msg, int msglen)
{
    const int m = r1 - r0, n = v1 - v0;
    if (n == 0 || m == 0) return 0;
    if (!gather_block(w, r0, r1, v0, v1, row_start, col, val, rhs)) {
        int small = n <= SMALL_BLOCK;
        for (int d = 0; d < (small ? 1 : 3); d++)
            if (solve_rows(r0, r1, d, small ? 3 : 1, row_start, col, val, rhs, x, w.opt, msg, msglen)) return 1;
        return 0;
    }
    if (n <= TINY_BLOCK) {
        TinyCost tc;
        tc.A = w.A.data();
        tc.m = m;
        tc.n = n;
        std::vector<double> &bd = w.bd;
        bd.resize((size_t)m);
        tc.b = bd.data();
        Eigen::VectorXd &p = w.tp;
        p.resize(n);
        std::vector<double> &out = w.p;
        out.resize(3 * (size_t)n);
        int finite = 1;
        for (int d = 0; d < 3 && finite; d++) {
            for (int i = 0; i < m; i++) bd[(size_t)i] = w.b[3 * (size_t)i + d];
            for (int j = 0; j < n; j++) p[j] = x[3 * (size_t)(v0 + j) + d];
            w.tiny.Solve(tc, &p);
            for (int j = 0; j < n; j++) {
                finite = finite && std::isfinite(p[j]);
                out[3 * (size_t)j + d] = p[j];
            }
        }
        if (finite) {
            std::memcpy(x + 3 * (size_t)v0, out.data(), sizeof(double) * 3 * (size_t)n);
            return 0;
        }
        /* a singular block (its normal equations have no Cholesky factor): ceres::Solve's QR below */
    }
    ceres::Problem problem(w.popt);
    /* per coordinate: b and p hold coordinate d contiguously; one Problem, three Solves */
    std::vector<double> &p = w.p;
    p.resize((size_t)n);
    std::vector<double> &bd = w.bd;
    bd.resize((size_t)m);
    w.cost.set(m, n, 1, w.A.data(), bd.data());
    problem.AddResidualBlock(&w.cost, nullptr, p.data());
    for (int d = 0; d < 3; d++) {
        for (int i = 0; i < m; i++) bd[(size_t)i] = w.b[3 * (size_t)i + d];
        for (int j = 0; j < n; j++) p[(size_t)j] = x[3 * (size_t)(v0 + j) + d];
        if (run_solve(w.opt, problem, msg, msglen)) return 1;
        for (int j = 0; j < n; j++) x[3 * (size_t)(v0 + j) + d] = p[(size_t)j];
    }
    return 0;
}

/* Batched path: many blocks in ONE SPARSE_NORMAL_CHOLESKY Solve.  Each block and coordinate is
 * one residual block (its rows as a dense matrix, BlockCost dim 1) over one parameter block (that
 * coordinate of its unknowns), so the Jacobian is block diagonal with dense blocks: Ceres forms
 * J^T J block by block and CHOLMOD factors the n x n blocks.  Ceres' per-Solve cost (problem
 * preprocessing, summary) is paid once per batch instead of three times per block.  Blocks whose
 * rows do not gather (solve_block's fallback) are solved on their own. */
namespace {
struct BatchItem {
    int it, m, n;
    std::vector<double> A, b[3], p[3];
    BlockCost cost[3];
};
}  // namespace

static int solve_batch(std::deque<BatchItem> &items, double *x, const int *item_var, const ceres::Solver::Options &o,
                       char *msg, int msglen)
{
    if (items.empty()) return 0;
    ceres::Problem::Options popt;
    popt.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(popt);
    for (BatchItem &b : items)
        for (int d = 0; d < 3; d++) {
            b.cost[d].set(b.m, b.n, 1, b.A.data(), b.b[d].data());
            problem.AddResidualBlock(&b.cost[d], nullptr, b.p[d].data());
        }
    if (run_solve(o, problem, msg, msglen)) return 1;
    for (BatchItem &b : items) {
        int v0 = item_var[b.it];
        for (int d = 0; d < 3; d++)
            for (int j = 0; j < b.n; j++) x[3 * (size_t)(v0 + j) + d] = b.p[d][(size_t)j];
    }
    return 0;
}

/* Jacobian entries (all coordinates) per batched Solve: bounds the batch's memory (~24 bytes an
 * entry with Ceres' copies) while keeping Ceres' fixed cost per Solve negligible. */
enum { BATCH_ENTRIES = 1 << 21 };

static int solve_batched(int nitem, const int *item_row, const int *item_var, const int *row_start, const int *col,
                         const double *val, const double *rhs, double *x, int threads, char *msg, int msglen)
{
    ceres::Solver::Options o;
    set_solver_options(o, threads, 0);
    BlockWorker w;
    set_solver_options(w.opt, 1, 1);
    std::deque<BatchItem> batch;
    long entries = 0;
    for (int it = 0; it < nitem; it++) {
        int r0 = item_row[it], r1 = item_row[it + 1], v0 = item_var[it], v1 = item_var[it + 1];
        int m = r1 - r0, n = v1 - v0;
        if (m == 0 || n == 0) continue;
        if (!gather_block(w, r0, r1, v0, v1, row_start, col, val, rhs)) {
            if (solve_block(w, r0, r1, v0, v1, row_start, col, val, rhs, x, msg, msglen)) return 1;
            continue;
        }
        batch.emplace_back();
        BatchItem &b = batch.back();
        b.it = it;
        b.m = m;
        b.n = n;
        b.A.swap(w.A);
        for (int d = 0; d < 3; d++) {
            b.b[d].resize((size_t)m);
            for (int i = 0; i < m; i++) b.b[d][(size_t)i] = w.b[3 * (size_t)i + d];
            b.p[d].resize((size_t)n);
            for (int j = 0; j < n; j++) b.p[d][(size_t)j] = x[3 * (size_t)(v0 + j) + d];
        }
        entries += 3L * m * n;
        if (entries >= BATCH_ENTRIES) {
            if (solve_batch(batch, x, item_var, o, msg, msglen)) return 1;
            batch.clear();
            entries = 0;
        }
    }
    return solve_batch(batch, x, item_var, o, msg, msglen);
}

extern "C" int q2n_ceres_linear_ls(int nvar, int nrow, const int *row_start, const int *col,
                                   const double *val, const double *rhs, double *x, int threads,
                                   int dense, int nitem, const int *item_row, const int *item_var, char *msg,
                                   int msglen)
{
    if (nvar == 0) return 0;
    if (threads < 1) threads = 1;
    ceres::Solver::Options o;
    set_solver_options(o, dense ? 1 : threads, dense);
    std::string bad;
    if (!o.IsValid(&bad)) {
        std::snprintf(msg, (size_t)msglen, "ceres options: %s", bad.c_str());
        return 1;
    }
    if (!dense) {
        if (nitem > 0) return solve_batched(nitem, item_row, item_var, row_start, col, val, rhs, x, threads, msg, msglen);
        for (int d = 0; d < 3; d++)
            if (solve_rows(0, nrow, d, 1, row_start, col, val, rhs, x, o, msg, msglen)) return 1;
        return 0;
    }
    /* Independent blocks, small DENSE_QR problems each (solve_block), spread over `threads`
     * workers (block i goes to worker i mod threads: the result does not depend on the thread
     * count). */
    std::vector<int> fail((size_t)threads, 0);
    std::vector<std::string> why((size_t)threads);
    auto work = [&](int wi) {
        char m[256] = "";
        BlockWorker w;
        w.opt = o;
        for (int it = wi; it < nitem; it += threads)
            if (solve_block(w, item_row[it], item_row[it + 1], item_var[it], item_var[it + 1], row_start, col, val,
                            rhs, x, m, (int)sizeof m)) {
                fail[(size_t)wi] = 1;
                why[(size_t)wi] = m;
                return;
            }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < threads; w++) pool.emplace_back(work, w);
    work(0);
    for (auto &t : pool) t.join();
    for (int w = 0; w < threads; w++)
        if (fail[(size_t)w]) {
            std::snprintf(msg, (size_t)msglen, "%s", why[(size_t)w].c_str());
            return 1;
        }
    return 0;
}
