/* Static-pivot complex sparse LU of a shifted pencil M = A + s B, and the two-sided inverse
 * iteration of wingmdao.stability.sensitivity.refine_pair on it (wingmdao/stability/pencil_lu.py).
 *
 * The complex sibling of wingmdao/timemarch/lu_kernel.c: A and B (real) are given on one CSC
 * pattern (the union of theirs), the row pivot order P comes from one SuperLU factorization (natural
 * column order) and the column structures of L and U of P M from lu_kernel.c's lu_symbolic, once
 * per pattern and pivot order. The numeric factorization is left-looking with the pivots fixed
 * (Gilbert & Peierls, SIAM J. Sci. Stat. Comput. 9, 1988); every solve, with M or with M^H, is
 * checked by its normwise backward error (Rigal & Gaches, J. ACM 14, 1967, in the infinity norm
 * with |M| |x| for ||M|| ||x||)
 *     berr = max_i |b - M x|_i / max_i (|M| |x| + |b|)_i      (|z| = |Re z| + |Im z|),
 * refined once when above the tolerance and reported to the caller (which then redoes the shift
 * with SuperLU and takes that factorization's pivot order) when still above. Not the
 * componentwise error of lu_kernel.c: inverse iteration solves with M nearly singular, where
 * x is ~1e10 larger along the eigenvector than b and SuperLU's own componentwise errors are
 * 1e-6 - 1e-2 (its normwise ones 3e-17 - 8e-15 on the PEGASUS pencils).
 *
 * Factor layout (n_lu = nl + nu + n complex): L below the diagonal by columns, U above the
 * diagonal by columns, then the diagonal of U; L has a unit diagonal; P M = L U.
 * Compiled with -fcx-fortran-rules: complex products without the C99 Annex G NaN/inf recovery
 * (what SuperLU's own complex arithmetic does); a zero or non-finite pivot is reported instead.
 */
#include <complex.h>
#include <math.h>
#include <string.h>

typedef double complex cplx;

typedef struct {
    int n, nnz;
    const int *indptr;  /* n + 1: CSC column pointers of the union pattern */
    const int *rows;    /* nnz: row of each nonzero */
    const int *prow;    /* nnz: row of each nonzero in P M (perm[rows[k]]) */
    const int *perm;    /* n: row i of M is row perm[i] of P M */
    const int *lp, *li; /* L strictly lower: column pointers (n + 1), rows */
    const int *up, *ui; /* U strictly upper: column pointers (n + 1), rows (ascending) */
} pencil_pattern;

int pencil_lu_version(void) { return 5; }

static inline double abs1(cplx z) { return fabs(creal(z)) + fabs(cimag(z)); }

/* Factors f (n_lu) of P M = L U, M = A + s B; a, b: the nnz real values of A and B on the
 * pattern; m, ma (nnz each): the values of M and their |.| (for the checks). x: n complex, zero on
 * entry and on return. Returns 0, or 1 + j for the first column j with a zero or non-finite pivot
 * (the factorization is completed all the same). */
int pencil_factor(const pencil_pattern *p, const double *a, const double *b, double sr, double si,
                  cplx *f, cplx *m, double *ma, cplx *x, double *growth)
{
    const int n = p->n, nl = p->lp[n], nu = p->up[n];
    const cplx s = CMPLX(sr, si);
    cplx *L = f, *U = f + nl, *D = U + nu;
    int bad = 0;
    for (int j = 0; j < n; ++j) {
        for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k) {
            const cplx v = a[k] + s * b[k];
            m[k] = v;
            ma[k] = abs1(v);
            x[p->prow[k]] = v;
        }
        for (int t = p->up[j]; t < p->up[j + 1]; ++t) {      /* ascending: topological order */
            const int k = p->ui[t];
            const cplx xk = x[k];
            U[t] = xk;
            x[k] = 0.0;
            for (int q = p->lp[k]; q < p->lp[k + 1]; ++q)
                x[p->li[q]] -= L[q] * xk;
        }
        const cplx piv = x[j];
        D[j] = piv;
        x[j] = 0.0;
        if (!bad && (piv == 0.0 || !isfinite(creal(piv)) || !isfinite(cimag(piv))))
            bad = 1 + j;
        for (int q = p->lp[j]; q < p->lp[j + 1]; ++q) {
            L[q] = x[p->li[q]] / piv;
            x[p->li[q]] = 0.0;
        }
    }
    /* growth = || |L| |U| || / || M || (infinity norms, |z| = |Re z| + |Im z|): the factors' backward
     * error bound |dM| <= gamma_n |L| |U| (Higham, Accuracy and Stability of Numerical Algorithms,
     * 2nd ed., Thm 9.3) relative to M, whatever the right-hand side. x is the work (2 n doubles). */
    double *w = (double *)x, *z = w + n, mnorm = 0.0, lunorm = 0.0;
    for (int i = 0; i < n; ++i) {
        w[i] = abs1(D[i]);
        z[i] = 0.0;
    }
    for (int j = 0; j < n; ++j)
        for (int t = p->up[j]; t < p->up[j + 1]; ++t)
            w[p->ui[t]] += abs1(U[t]);            /* w = |U| e */
    for (int j = 0; j < n; ++j)
        for (int q = p->lp[j]; q < p->lp[j + 1]; ++q)
            z[p->li[q]] += abs1(L[q]) * w[j];     /* z = (|L| - I) w */
    for (int i = 0; i < n; ++i) {
        const double r = z[i] + w[i];
        if (!(r <= lunorm))
            lunorm = r;
    }
    for (int i = 0; i < n; ++i)
        z[i] = 0.0;
    for (int j = 0; j < n; ++j)
        for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k)
            z[p->rows[k]] += ma[k];                /* row sums of |M| */
    for (int i = 0; i < n; ++i)
        if (z[i] > mnorm)
            mnorm = z[i];
    memset(x, 0, (size_t)n * sizeof(cplx));
    growth[0] = mnorm > 0.0 ? lunorm / mnorm : INFINITY;
    if (isnan(growth[0]))
        growth[0] = INFINITY;
    return bad;
}

#define LU_T cplx
#define LU_CONJ(z) conj(z)
#define LU_SOLVE pencil_triangular_solve
#include "../timemarch/lu_triangular.h"

/* x := M^-1 x (trans = 0) or M^-H x (trans != 0) in place; y: n complex work. */
void pencil_solve(const pencil_pattern *p, const cplx *f, cplx *x, int trans, cplx *y)
{
    pencil_triangular_solve(p->n, p->perm, NULL, p->lp, p->li, p->up, p->ui, f, x, trans, y);
}

/* res = rhs - M x (M^H x for trans) and the normwise backward error
 * max_i |res_i| / max_i (|M| |x| + |rhs|)_i (inf for a zero scale with a nonzero residual, and
 * for NaN); work: n doubles. */
double pencil_berr(const pencil_pattern *p, const cplx *m, const double *ma, const cplx *x, const cplx *rhs,
                   int trans, cplx *res, double *work)
{
    const int n = p->n;
    double berr;
    if (trans) {            /* (M^H x)_j = sum_k conj(m_k) x[rows_k] over column j */
        for (int j = 0; j < n; ++j) {
            cplx acc = 0.0;
            double sa = 0.0;
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k) {
                const cplx xr = x[p->rows[k]];
                acc += conj(m[k]) * xr;
                sa += ma[k] * abs1(xr);
            }
            res[j] = rhs[j] - acc;
            work[j] = sa + abs1(rhs[j]);
        }
    } else {
        for (int i = 0; i < n; ++i) {
            res[i] = rhs[i];
            work[i] = abs1(rhs[i]);
        }
        for (int j = 0; j < n; ++j) {
            const cplx xj = x[j];
            const double aj = abs1(xj);
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k) {
                res[p->rows[k]] -= m[k] * xj;
                work[p->rows[k]] += ma[k] * aj;
            }
        }
    }
    double rmax = 0.0, smax = 0.0;
    for (int i = 0; i < n; ++i) {
        const double r = abs1(res[i]);
        if (!(r <= rmax))           /* also NaN */
            rmax = r;
        if (work[i] > smax)
            smax = work[i];
    }
    berr = smax > 0.0 ? rmax / smax : (rmax == 0.0 ? 0.0 : INFINITY);
    return isnan(berr) ? INFINITY : berr;
}

/* Checked solve x = M^-1 rhs (M^-H for trans), refined once when berr > tol; returns the final
 * backward error. work: 3 n complex. */
double pencil_solve_checked(const pencil_pattern *p, const cplx *m, const double *ma, const cplx *f,
                            const cplx *rhs, cplx *x, int trans, double tol, cplx *work)
{
    const int n = p->n;
    cplx *y = work, *res = work + n, *d = work + 2 * n;
    double *sw = (double *)d;     /* the scale (n doubles) fits in d, free until the refinement */
    memcpy(x, rhs, (size_t)n * sizeof(cplx));
    pencil_solve(p, f, x, trans, y);
    double berr = pencil_berr(p, m, ma, x, rhs, trans, res, sw);
    if (berr <= tol)
        return berr;
    memcpy(d, res, (size_t)n * sizeof(cplx));
    pencil_solve(p, f, d, trans, y);
    for (int i = 0; i < n; ++i)
        x[i] += d[i];
    return pencil_berr(p, m, ma, x, rhs, trans, res, (double *)y);
}

/* y = V x (trans = 0) or V^T x (trans != 0) for a real matrix V with values v on the pattern. */
static void matvec(const pencil_pattern *p, const double *v, const cplx *x, int trans, cplx *y)
{
    const int n = p->n;
    if (trans) {
        for (int j = 0; j < n; ++j) {
            cplx acc = 0.0;
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k)
                acc += v[k] * x[p->rows[k]];
            y[j] = acc;
        }
    } else {
        memset(y, 0, (size_t)n * sizeof(cplx));
        for (int j = 0; j < n; ++j) {
            const cplx xj = x[j];
            for (int k = p->indptr[j]; k < p->indptr[j + 1]; ++k)
                y[p->rows[k]] += v[k] * xj;
        }
    }
}

static cplx vdot(int n, const cplx *x, const cplx *y)     /* x^H y */
{
    cplx s = 0.0;
    for (int i = 0; i < n; ++i)
        s += conj(x[i]) * y[i];
    return s;
}

static double norm2(int n, const cplx *x)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i)
        s += creal(x[i]) * creal(x[i]) + cimag(x[i]) * cimag(x[i]);
    return sqrt(s);
}

/* |a - b ph / |ph||, ph = b^H a: the phase-aligned change of a unit vector */
static double change(int n, const cplx *a, const cplx *b)
{
    const cplx ph = vdot(n, b, a);
    const cplx r = ph != 0.0 ? ph / cabs(ph) : 1.0;
    double s = 0.0;
    for (int i = 0; i < n; ++i) {
        const cplx d = a[i] - b[i] * r;
        s += creal(d) * creal(d) + cimag(d) * cimag(d);
    }
    return sqrt(s);
}

/* One shift of the two-sided inverse iteration (refine_pair): with the factors f of
 * M = A + s B (values m, |m| from pencil_factor), up to `iterations` steps
 *     v <- M^-1 (B v) / |.|,  u <- M^-H (B^T u) / |.|,  lam = -u^H A v / u^H B v,
 * converged when |lam - lam_old| <= tol |lam| and both vectors changed by at most sqrt(tol).
 * v, u (unit), bv = B v, lam[2] (re, im), lam_old[2]: in / out (the state after the last step).
 * work: 7 n complex. The solves of the first `checked` steps are checked (pencil_solve_checked;
 * the factors' growth, pencil_factor, bounds the backward error of every solve). Returns 1
 * converged, 0 not converged, -1 - step when a checked solve's backward error stayed above btol after one refinement (v, u, bv, lam are then
 * partly updated: the caller redoes the shift from its own copies). berr[0]: the largest
 * backward error of the accepted solves. steps[0]: the steps taken. */
int pencil_iterate(const pencil_pattern *p, const double *a, const double *b, const cplx *m, const double *ma,
                   const cplx *f, cplx *v, cplx *u, cplx *bv, double *lam, double *lam_old, int iterations,
                   double tol, double btol, int checked, cplx *work, double *berr, int *steps)
{
    const int n = p->n;
    cplx *vn = work, *un = work + n, *rhs = work + 2 * n, *av = work + 3 * n, *ws = work + 4 * n;
    cplx l = CMPLX(lam[0], lam[1]), lo = CMPLX(lam_old[0], lam_old[1]);
    const double vtol = sqrt(tol);
    int status = 0;
    for (int it = 0; it < iterations; ++it) {
        steps[0] = it + 1;
        matvec(p, b, u, 1, rhs);                      /* B^H u = B^T u (B real) */
        if (it < checked) {                           /* a posteriori check of the first steps */
            double e = pencil_solve_checked(p, m, ma, f, bv, vn, 0, btol, ws);
            const double eh = pencil_solve_checked(p, m, ma, f, rhs, un, 1, btol, ws);
            if (eh > e || isnan(eh))
                e = eh;
            if (!(e <= btol)) {
                status = -1 - it;
                break;
            }
            if (e > berr[0])
                berr[0] = e;
        } else {
            memcpy(vn, bv, (size_t)n * sizeof(cplx));
            pencil_solve(p, f, vn, 0, ws);
            memcpy(un, rhs, (size_t)n * sizeof(cplx));
            pencil_solve(p, f, un, 1, ws);
        }
        const double nv = norm2(n, vn), nu = norm2(n, un);
        for (int i = 0; i < n; ++i) {
            vn[i] /= nv;
            un[i] /= nu;
        }
        const double c1 = change(n, vn, v), c2 = change(n, un, u);
        const double dv = c1 > c2 ? c1 : c2;
        memcpy(v, vn, (size_t)n * sizeof(cplx));
        memcpy(u, un, (size_t)n * sizeof(cplx));
        matvec(p, b, v, 0, bv);
        matvec(p, a, v, 0, av);
        l = -vdot(n, u, av) / vdot(n, u, bv);
        if (cabs(l - lo) <= tol * cabs(l) && dv <= vtol) {
            status = 1;
            break;
        }
        lo = l;
    }
    lam[0] = creal(l);
    lam[1] = cimag(l);
    lam_old[0] = creal(lo);
    lam_old[1] = cimag(lo);
    return status;
}

/* YA = A X, YB = B X (trans = 0) or A^T X, B^T X (trans != 0) for the k columns of X (n x k,
 * row-major, as YA and YB): the products of the two-sided Rayleigh-Ritz projection
 * (sensitivity._ritz), in the summation order of SciPy's CSC / CSR products. */
void pencil_products(const pencil_pattern *p, const double *a, const double *b, const cplx *X, int k,
                     int trans, cplx *YA, cplx *YB)
{
    const int n = p->n;
    memset(YA, 0, (size_t)n * k * sizeof(cplx));
    memset(YB, 0, (size_t)n * k * sizeof(cplx));
    for (int j = 0; j < n; ++j)
        for (int q = p->indptr[j]; q < p->indptr[j + 1]; ++q) {
            const int i = p->rows[q];
            const double av = a[q], bv = b[q];
            if (trans) {                /* (A^T X)[j] += a_q X[i] */
                const cplx *x = X + (size_t)i * k;
                cplx *ya = YA + (size_t)j * k, *yb = YB + (size_t)j * k;
                for (int c = 0; c < k; ++c) {
                    ya[c] += av * x[c];
                    yb[c] += bv * x[c];
                }
            } else {                    /* (A X)[i] += a_q X[j] */
                const cplx *x = X + (size_t)j * k;
                cplx *ya = YA + (size_t)i * k, *yb = YB + (size_t)i * k;
                for (int c = 0; c < k; ++c) {
                    ya[c] += av * x[c];
                    yb[c] += bv * x[c];
                }
            }
        }
}
