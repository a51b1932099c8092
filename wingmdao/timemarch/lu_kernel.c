/* Static-pivot sparse LU and the BDF tangent/adjoint sweeps of wingmdao.timemarch.adjoint.
 *
 * Data-driven: the symbolic structure of P A = L U (row permutation P from wingmdao/timemarch/
 * static_lu.py, column structures of L and U from lu_symbolic below, once per pattern and pivot
 * order) comes in as integer arrays, so one compiled library serves every pattern. Left-looking numeric factorization
 * (Gilbert & Peierls, SIAM J. Sci. Stat. Comput. 9, 1988) with the pivots fixed; each solve is
 * checked by its componentwise backward error (Oettli & Prager, Numer. Math. 6, 1964)
 *     berr = max_i |b - M x|_i / (|M| |x| + |b|)_i,
 * with the rows whose scale (|M| |x| + |b|)_i is round-off measured normwise instead (Arioli,
 * Demmel & Duff, SIAM J. Matrix Anal. Appl. 10(2), 1989, 165-190, Sec. 3: the rows i with
 * (|M| |x| + |b|)_i <= 1000 n eps (||M_i||_inf ||x||_inf + |b_i|) take
 *     |b - M x|_i / ((|M| |x|)_i + ||M_i||_inf ||x||_inf)),
 * refined once when above the tolerance, and reported to the caller (which uses SuperLU for that
 * step) when still above. Indices are int32, values double, arrays C-contiguous.
 *
 * Factor layout (n_lu = nl + nu + n doubles): L below the diagonal by columns, U above the
 * diagonal by columns, then the diagonal of U. L has a unit diagonal. P A Q = L U: the column
 * order Q (qcol) is a fill-reducing order given by the caller (identity: natural order).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int n, nnz;
    const int *indptr;  /* n + 1: CSC column pointers of A */
    const int *rows;    /* nnz: row of each nonzero of A */
    const int *prow;    /* nnz: row of each nonzero in P A (perm[rows[k]]) */
    const int *perm;    /* n: row i of A is row perm[i] of P A */
    const int *lp, *li; /* L strictly lower: column pointers (n + 1), rows */
    const int *up, *ui; /* U strictly upper: column pointers (n + 1), rows (ascending) */
    const int *qcol;    /* n: column j of P A Q is column qcol[j] of A (fill-reducing order) */
} lu_pattern;

int lu_kernel_version(void) { return 10; }

/* Matrices factored together by lu_factor_lanes (one SIMD lane each). */
#define LU_W 4
typedef double lu_v4 __attribute__((vector_size(32), aligned(8)));

/* Factors of nw <= LU_W matrices at once, nonzeros a[w] into f[w] (n_lu each): a left-looking
 * LU with the fixed pivots of the pattern on each lane (the lanes are the matrices; a lane of
 * fewer than LU_W matrices repeats matrix 0), so the index loads and the loop control of the
 * short columns are shared by LU_W matrices. A zero pivot gives inf/NaN factors (caught by the
 * backward error). xw: n LU_W doubles, zero on entry and on return; fw:
 * n_lu LU_W doubles (the interleaved factors, copied out to f at the end). */
static void lu_factor_lanes(const lu_pattern *p, int nw, const double *const *a, double *const *f,
                            double *xw, double *fw)
{
    const int n = p->n, nl = p->lp[n], nu = p->up[n], nlu = nl + nu + n;
    lu_v4 *X = (lu_v4 *)xw, *L = (lu_v4 *)fw, *U = L + nl, *D = U + nu;
    for (int j = 0; j < n; ++j) {
        const int c = p->qcol[j];
        for (int k = p->indptr[c]; k < p->indptr[c + 1]; ++k) {
            lu_v4 v;
            for (int w = 0; w < LU_W; ++w)
                v[w] = a[w < nw ? w : 0][k];
            X[p->prow[k]] = v;
        }
        for (int t = p->up[j]; t < p->up[j + 1]; ++t) {      /* ascending: topological order */
            const int k = p->ui[t];
            const lu_v4 xk = X[k];
            U[t] = xk;
            X[k] = (lu_v4){0.0, 0.0, 0.0, 0.0};
            for (int q = p->lp[k]; q < p->lp[k + 1]; ++q)
                X[p->li[q]] -= L[q] * xk;
        }
        const lu_v4 piv = X[j];
        D[j] = piv;
        X[j] = (lu_v4){0.0, 0.0, 0.0, 0.0};
        for (int q = p->lp[j]; q < p->lp[j + 1]; ++q) {
            L[q] = X[p->li[q]] / piv;
            X[p->li[q]] = (lu_v4){0.0, 0.0, 0.0, 0.0};
        }
    }
    for (int w = 0; w < nw; ++w) {
        double *fo = f[w];
        for (int i = 0; i < nlu; ++i)
            fo[i] = fw[(size_t)i * LU_W + w];
    }
}

/* Factors of m matrices with nonzeros a (m x nnz) into f (m x n_lu), LU_W at a time; xw: n LU_W doubles, zero on entry and on
 * return; fw: n_lu LU_W doubles. */
void lu_factor_batch(const lu_pattern *p, int m, const double *a, double *f, double *xw, double *fw)
{
    const int n = p->n, nlu = p->lp[n] + p->up[n] + n;
    for (int s = 0; s < m; s += LU_W) {
        const int nw = m - s < LU_W ? m - s : LU_W;
        const double *as[LU_W];
        double *fs[LU_W];
        for (int w = 0; w < nw; ++w) {
            as[w] = a + (size_t)(s + w) * p->nnz;
            fs[w] = f + (size_t)(s + w) * nlu;
        }
        lu_factor_lanes(p, nw, as, fs, xw, fw);
    }
}

#define LU_T double
#define LU_CONJ(z) (z)
#define LU_SOLVE lu_triangular_solve
#include "lu_triangular.h"

/* x := M^-1 b in place (M = A for trans = 0, A^T otherwise); work: n doubles. */
void lu_solve(const lu_pattern *p, const double *f, double *x, int trans, double *work)
{
    lu_triangular_solve(p->n, p->perm, p->qcol, p->lp, p->li, p->up, p->ui, f, x, trans, work);
}

/* res = b - M x and the componentwise backward error (inf when a scale is zero but its residual
 * is not, or for NaN). A row whose scale s_i = (|M| |x| + |b|)_i is at most 1000 n eps
 * (||M_i||_inf ||x||_inf + |b_i|) is measured by |res_i| / ((|M| |x|)_i + ||M_i||_inf ||x||_inf)
 * (Arioli, Demmel & Duff 1989): its exact value would be zero, and the relative measure would
 * compare the round-off of a solution component that is zero in exact arithmetic (the mirror
 * components of a symmetric half model's adjoint) with itself. work: 2 n doubles. */
double lu_berr(const lu_pattern *p, const double *a, const double *x, const double *b, int trans,
               double *res, double *work)
{
    const int n = p->n;
    double *rown = work + n;        /* ||M_i||_inf */
    double berr = 0.0, xn = 0.0;
    for (int i = 0; i < n; ++i)
        if (fabs(x[i]) > xn)
            xn = fabs(x[i]);
    if (trans) {            /* (A^T x)_j = sum_k a_k x[rows_k] over column j */
        for (int j = 0; j < n; ++j) {
            double s = 0.0, sa = 0.0, m = 0.0;
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k) {
                const double v = a[k] * x[p->rows[k]];
                s += v;
                sa += fabs(v);
                if (fabs(a[k]) > m)
                    m = fabs(a[k]);
            }
            res[j] = b[j] - s;
            work[j] = sa;
            rown[j] = m;
        }
    } else {
        for (int i = 0; i < n; ++i) {
            res[i] = b[i];
            work[i] = 0.0;
            rown[i] = 0.0;
        }
        for (int j = 0; j < n; ++j) {
            const double xj = x[j];
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k) {
                const double v = a[k] * xj;
                const int i = p->rows[k];
                res[i] -= v;
                work[i] += fabs(v);
                if (fabs(a[k]) > rown[i])
                    rown[i] = fabs(a[k]);
            }
        }
    }
    const double tiny = 1000.0 * (double)n * 2.220446049250313e-16;
    for (int i = 0; i < n; ++i) {
        const double r = fabs(res[i]), ax = work[i], bi = fabs(b[i]), s = ax + bi;
        const double norm = rown[i] * xn;
        double e;
        if (s > tiny * (norm + bi))
            e = r / s;
        else {
            const double s2 = ax + norm;
            e = s2 > 0.0 ? r / s2 : (r == 0.0 ? 0.0 : INFINITY);
        }
        if (isnan(e))
            e = INFINITY;
        if (e > berr)
            berr = e;
    }
    return berr;
}

/* Refinements at most per checked solve. The Newton matrix of a symmetric half model (symmetry
 * conditions on several nodes of a shear-rigid beam: redundant kinematic rows, condition ~1e20)
 * can need a second one; the first suffices elsewhere. */
#define LU_REFINE 2

/* Checked solve: x = M^-1 b, refined (at most LU_REFINE times) while berr > tol. Returns the
 * final backward error; *refined is set to 1 when a refinement was made. work: 3 n doubles. */
static double checked_solve(const lu_pattern *p, const double *f, const double *a, const double *b,
                            double *x, int trans, double tol, int *refined, double *work)
{
    const int n = p->n;
    /* lu_berr's 2 n of work, then res; the correction d shares lu_berr's second n */
    double *res = work + 2 * n, *d = work + n;
    memcpy(x, b, (size_t)n * sizeof(double));
    lu_solve(p, f, x, trans, work);
    double berr = lu_berr(p, a, x, b, trans, res, work);
    *refined = 0;
    for (int it = 0; it < LU_REFINE && !(berr <= tol); ++it) {
        *refined = 1;
        memcpy(d, res, (size_t)n * sizeof(double));
        lu_solve(p, f, d, trans, work);
        for (int i = 0; i < n; ++i)
            x[i] += d[i];
        berr = lu_berr(p, a, x, b, trans, res, work);
    }
    return berr;
}

/* Solve one matrix (nonzeros a, factors f): x = M^-1 b; returns berr, res = b - M x.
 * work: 2 n doubles. */
double lu_solve_checked(const lu_pattern *p, const double *f, const double *a, const double *b,
                        double *x, double *res, int trans, double *work)
{
    memcpy(x, b, (size_t)p->n * sizeof(double));
    lu_solve(p, f, x, trans, work);
    return lu_berr(p, a, x, b, trans, res, work);
}

/* The history of the sweeps. Steps are absolute indices 0..n_time-1; the per-step arrays a
 * (nonzeros of A_n, stride nnz) and jd (nonzeros of dR/dxdot, stride njd) start at step off.
 * The rate Jacobian's used nonzeros are jd[src[k]] at (drow[k], dcol[k]), k < nd. */
typedef struct {
    int n_time, off, nd, njd;
    const double *a, *jd;
    const int *src, *drow, *dcol;
    const double *coef;             /* n_time x 3: alpha_k(n)/dt */
    const unsigned char *same;      /* n_time: A_n equals A_{n-1} */
    double tol;
} sweep_data;

/* The factors of the steps of a sweep, LU_W steps at a time (lu_factor_lanes): f holds LU_W
 * factor slots (n_lu each) then the interleaved scratch (n_lu LU_W), xw n LU_W doubles (zero).
 * Steps whose matrix equals the step before's (in sweep order) reuse its factors. */
typedef struct {
    const lu_pattern *p;
    const sweep_data *s;
    double *f, *fw, *xw;
    int first, count, dir;          /* the slots hold steps first, first + dir, ... (count) */
    int have;                       /* the step of the factors last used (-1: none) */
    const double *cur;              /* its factors */
    int factored;                   /* matrices factored (statistics) */
} factor_feed;

/* The factors of step m, the next step of the sweep (direction dir: -1 adjoint, +1 tangent);
 * end: the last step of the sweep (a batch does not go past it). */
static const double *feed_factors(factor_feed *ff, int m, int end)
{
    const lu_pattern *p = ff->p;
    const sweep_data *s = ff->s;
    const int nlu = p->lp[p->n] + p->up[p->n] + p->n;
    /* A_m equals the matrix of the step before in sweep order */
    const int prev = m - ff->dir;
    if (ff->have == prev && ff->cur && s->same[ff->dir < 0 ? prev : m]) {
        ff->have = m;
        return ff->cur;
    }
    int slot = (m - ff->first) * ff->dir;
    if (slot < 0 || slot >= ff->count) {
        /* a new batch: steps m, m + dir, ..., at most LU_W, not past end; a step equal to its
         * predecessor in sweep order ends the batch (it reuses that factor) */
        const double *as[LU_W];
        double *fs[LU_W];
        int nw = 0;
        for (int q = m; nw < LU_W && (q - end) * ff->dir <= 0; q += ff->dir) {
            if (nw > 0 && s->same[ff->dir < 0 ? q - ff->dir : q])
                break;
            as[nw] = s->a + (size_t)(q - s->off) * p->nnz;
            fs[nw] = ff->f + (size_t)nw * nlu;
            ++nw;
        }
        lu_factor_lanes(p, nw, as, fs, ff->xw, ff->fw);
        ff->factored += nw;
        ff->first = m;
        ff->count = nw;
        slot = 0;
    }
    ff->have = m;
    ff->cur = ff->f + (size_t)slot * nlu;
    return ff->cur;
}

/* Adjoint sweep A_n^T lam_n = g_n - c(n+1,1) R_{n+1}^T lam_{n+1} - c(n+2,2) R_{n+2}^T lam_{n+2}
 * for n = hi, hi-1, ..., lo (lo >= 1). rhs and lam are n_time x n. Returns the step at which a
 * refined solve still failed (lam[step] not set; b holds its right-hand side), or lo - 1.
 * f: (2 LU_W) n_lu doubles; work: (4 + LU_W) n, its last LU_W n zero; counts[0] += refined steps,
 * counts[1] += factored matrices. */
int adjoint_sweep(const lu_pattern *p, const sweep_data *s, int hi, int lo, const double *rhs,
                  double *lam, double *f, double *b, double *work, int *counts)
{
    const int n = p->n, nlu = p->lp[n] + p->up[n] + n;
    factor_feed ff = {p, s, f, f + (size_t)LU_W * nlu, work + 4 * n, 0, 0, -1, -1, 0, 0};
    for (int m = hi; m >= lo; --m) {
        const double *am = s->a + (size_t)(m - s->off) * p->nnz;
        memcpy(b, rhs + (size_t)m * n, (size_t)n * sizeof(double));
        for (int k = 1; k <= 2; ++k) {
            const int r = m + k;
            if (r >= s->n_time)
                break;
            const double c = s->coef[3 * r + k];
            if (c == 0.0)
                continue;
            const double *jd = s->jd + (size_t)(r - s->off) * s->njd, *lr = lam + (size_t)r * n;
            for (int q = 0; q < s->nd; ++q)
                b[s->dcol[q]] -= c * jd[s->src[q]] * lr[s->drow[q]];
        }
        const double *fm = feed_factors(&ff, m, lo);
        int refined;
        double berr = checked_solve(p, fm, am, b, lam + (size_t)m * n, 1, s->tol, &refined, work + n);
        counts[0] += refined;
        if (!(berr <= s->tol)) {
            counts[1] += ff.factored;
            return m;
        }
    }
    counts[1] += ff.factored;
    return lo - 1;
}

/* Tangent sweep A_n dx_n = r_n - R_n (c(n,1) dx_{n-1} + c(n,2) dx_{n-2}) for n = lo..hi
 * (lo >= 1). Returns the step at which a refined solve still failed (b holds its right-hand
 * side), or hi + 1. Buffers and counts as adjoint_sweep; work: (5 + LU_W) n, the LU_W n after
 * the first 4 n zero. */
int tangent_sweep(const lu_pattern *p, const sweep_data *s, int lo, int hi, const double *rhs,
                  double *dx, double *f, double *b, double *work, int *counts)
{
    const int n = p->n, nlu = p->lp[n] + p->up[n] + n;
    factor_feed ff = {p, s, f, f + (size_t)LU_W * nlu, work + 4 * n, 0, 0, 1, -1, 0, 0};
    double *h = work + (4 + LU_W) * n;       /* history combination, n doubles */
    for (int m = lo; m <= hi; ++m) {
        const double *am = s->a + (size_t)(m - s->off) * p->nnz;
        const double *jd = s->jd + (size_t)(m - s->off) * s->njd;
        const double c1 = s->coef[3 * m + 1], c2 = m >= 2 ? s->coef[3 * m + 2] : 0.0;
        const double *d1 = dx + (size_t)(m - 1) * n, *d2 = m >= 2 ? dx + (size_t)(m - 2) * n : d1;
        for (int i = 0; i < n; ++i)
            h[i] = c1 * d1[i] + c2 * d2[i];
        memcpy(b, rhs + (size_t)m * n, (size_t)n * sizeof(double));
        for (int q = 0; q < s->nd; ++q)
            b[s->drow[q]] -= jd[s->src[q]] * h[s->dcol[q]];
        const double *fm = feed_factors(&ff, m, hi);
        int refined;
        double berr = checked_solve(p, fm, am, b, dx + (size_t)m * n, 0, s->tol, &refined, work + n);
        counts[0] += refined;
        if (!(berr <= s->tol)) {
            counts[1] += ff.factored;
            return m;
        }
    }
    counts[1] += ff.factored;
    return hi + 1;
}

/* out[t, oi[k]] += data[t, k] * vec[t, ii[k]] for t < nt, k < nnz (out nt x nout, vec nt x nin);
 * with sum_time, out is one row (the sum over t), summed per nonzero first in acc (nnz doubles,
 * zero on entry): consecutive nonzeros of a CasADi pattern share their column, and adding them
 * into one output element serialises the additions on its latency. */
void hist_product(int nt, int nnz, const double *data, const int *oi, const int *ii,
                  const double *vec, int nin, double *out, int nout, int sum_time, double *acc)
{
    if (sum_time) {
        for (int t = 0; t < nt; ++t) {
            const double *d = data + (size_t)t * nnz, *v = vec + (size_t)t * nin;
            for (int k = 0; k < nnz; ++k)
                acc[k] += d[k] * v[ii[k]];
        }
        for (int k = 0; k < nnz; ++k)
            out[oi[k]] += acc[k];
        return;
    }
    for (int t = 0; t < nt; ++t) {
        const double *d = data + (size_t)t * nnz, *v = vec + (size_t)t * nin;
        double *o = out + (size_t)t * nout;
        for (int k = 0; k < nnz; ++k)
            o[oi[k]] += d[k] * v[ii[k]];
    }
}

/* Newton-matrix nonzeros of nt steps: out[t, dx[k]] = jx[t, sx[k]] (k < nx), then
 * out[t, dd[k]] += c[t] jd[t, sd[k]] (k < ndd); out nt x nout is overwritten. same[t] = 1 when
 * row t equals row t - 1 (same[0] = 0). With known_x (njx flags; known_d, njd) the whole rows of
 * jx and jd are checked in the same pass (while in cache) for nonzeros outside the known columns:
 * those are flagged in new_x, new_d and counted in the return value (0: the pattern holds). */
int assemble_newton(int nt, const double *jx, int njx, const int *sx, const int *dxi, int nx,
                    const double *jd, int njd, const int *sd, const int *dd, int ndd,
                    const double *c, double *out, int nout, unsigned char *same,
                    const unsigned char *known_x, const unsigned char *known_d,
                    unsigned char *new_x, unsigned char *new_d)
{
    int found = 0;
    for (int t = 0; t < nt; ++t) {
        const double *x = jx + (size_t)t * njx, *d = jd + (size_t)t * njd;
        double *o = out + (size_t)t * nout;
        if (known_x) {      /* a branch-free (vectorised) test first; flags only when it finds one */
            int any = 0;
            for (int k = 0; k < njx; ++k)
                any |= (x[k] != 0.0) & (known_x[k] == 0);
            for (int k = 0; k < njd; ++k)
                any |= (d[k] != 0.0) & (known_d[k] == 0);
            if (any) {
                for (int k = 0; k < njx; ++k)
                    if (x[k] != 0.0 && !known_x[k]) {
                        new_x[k] = 1;
                        ++found;
                    }
                for (int k = 0; k < njd; ++k)
                    if (d[k] != 0.0 && !known_d[k]) {
                        new_d[k] = 1;
                        ++found;
                    }
            }
        }
        memset(o, 0, (size_t)nout * sizeof(double));
        for (int k = 0; k < nx; ++k)
            o[dxi[k]] = x[sx[k]];
        const double ct = c[t];
        for (int k = 0; k < ndd; ++k)
            o[dd[k]] += ct * d[sd[k]];
        int eq = t > 0;
        for (int k = 0; eq && k < nout; ++k)
            eq = o[k] == o[k - nout];
        same[t] = (unsigned char)eq;
    }
    return found;
}

/* out[k] |= (d[t, k] != 0) for t < nt (d nt x ncol). */
void nonzero_columns(int nt, int ncol, const double *d, unsigned char *out)
{
    for (int t = 0; t < nt; ++t) {
        const double *r = d + (size_t)t * ncol;
        for (int k = 0; k < ncol; ++k)
            out[k] |= r[k] != 0.0;
    }
}

/* A compiled CasADi function (C entry point of its generated code) at nt instants: input i of
 * instant t is in[i] + t * istride[i] (stride 0: the same at every instant), output k is written
 * straight to out[k] + t * ostride[k] (the rows of the caller's history arrays: no copies).
 * arg, res, iw, w: the function's work arrays (sizes from NAME_work). Returns 0, or 1 + the
 * instant at which the function reported a failure. */
typedef int (*casadi_entry)(const double **arg, double **res, long long *iw, double *w, int mem);

int eval_history(void *fun, int nt, int n_in, const double *const *in, const long long *istride,
                 int n_out, double *const *out, const long long *ostride, const double **arg,
                 double **res, long long *iw, double *w)
{
    casadi_entry f = (casadi_entry)fun;
    for (int t = 0; t < nt; ++t) {
        for (int i = 0; i < n_in; ++i)
            arg[i] = in[i] + (size_t)t * (size_t)istride[i];
        for (int k = 0; k < n_out; ++k)
            res[k] = out[k] + (size_t)t * (size_t)ostride[k];
        if (f(arg, res, iw, w, 0))
            return t + 1;
    }
    return 0;
}

/* Min-heap of row indices (symbolic factorization: the next-smallest k of a growing column). */
static void heap_push(int *h, int *size, int v)
{
    int i = (*size)++;
    while (i > 0) {
        int parent = (i - 1) / 2;
        if (h[parent] <= v)
            break;
        h[i] = h[parent];
        i = parent;
    }
    h[i] = v;
}

static int heap_pop(int *h, int *size)
{
    int top = h[0], v = h[--(*size)], i = 0, n = *size;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= n)
            break;
        if (c + 1 < n && h[c + 1] < h[c])
            ++c;
        if (v <= h[c])
            break;
        h[i] = h[c];
        i = c;
    }
    if (n > 0)
        h[i] = v;
    return top;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Row i enters the structure of column j (once: mark): above the diagonal onto the heap of rows
 * still to eliminate, below it into the column of L, on it as the pivot. */
static void visit_row(int i, int j, int *mark, int *heap, int *hs, int *low, int *nlow, int *diag)
{
    if (mark[i] == j)
        return;
    mark[i] = j;
    if (i < j)
        heap_push(heap, hs, i);
    else if (i > j)
        low[(*nlow)++] = i;
    else
        *diag = 1;
}

/* Column structures of unit-lower L (strictly below the diagonal) and U (strictly above) of the
 * CSC pattern (indptr, prow) of the row-permuted matrix P A, no further pivoting (the symbolic
 * step of the left-looking LU of Gilbert & Peierls 1988): column j of L + U is A(:, j) closed under
 * "row k < j present => rows of L(:, k) present", k taken in increasing order (a min-heap), which
 * is also the order in which the numeric factorization applies the columns of L. Writes
 * lp/up (n + 1) and li/ui (rows of L ascending, of U ascending) up to cap_l/cap_u entries.
 * work: 3 n ints (heap, marks, column of L). Returns 0; 1 when a capacity is too small (the
 * needed sizes are not known: the caller grows them and calls again); -1 - j when column j has a
 * structurally zero pivot. */
int lu_symbolic(int n, const int *indptr, const int *prow, int *lp, int *li, int cap_l,
                int *up, int *ui, int cap_u, int *work)
{
    int *heap = work, *mark = work + n, *low = work + 2 * n;
    int nl = 0, nu = 0;
    for (int i = 0; i < n; ++i)
        mark[i] = -1;
    lp[0] = up[0] = 0;
    for (int j = 0; j < n; ++j) {
        int hs = 0, nlow = 0, diag = 0;
        for (int k = indptr[j]; k < indptr[j + 1]; ++k)
            visit_row(prow[k], j, mark, heap, &hs, low, &nlow, &diag);
        while (hs > 0) {
            int k = heap_pop(heap, &hs);
            if (nu >= cap_u)
                return 1;
            ui[nu++] = k;
            for (int t = lp[k]; t < lp[k + 1]; ++t)
                visit_row(li[t], j, mark, heap, &hs, low, &nlow, &diag);
        }
        if (!diag)
            return -1 - j;
        if (nl + nlow > cap_l)
            return 1;
        qsort(low, (size_t)nlow, sizeof(int), cmp_int);
        memcpy(li + nl, low, (size_t)nlow * sizeof(int));
        nl += nlow;
        lp[j + 1] = nl;
        up[j + 1] = nu;
    }
    return 0;
}
