/* The triangular solves of a static-pivot sparse LU, P M Q = L U: one source for the real kernel
 * (lu_kernel.c: double, M^T) and the complex one (wingmdao/stability/pencil_lu.c: double complex,
 * M^H). wingmdao.utils.c_library inserts this file where a kernel includes it, after the kernel
 * has defined
 *     LU_T       the scalar type,
 *     LU_CONJ(z) the conjugate of a scalar (z itself for a real one),
 *     LU_SOLVE   the name of the function.
 *
 * Factor layout (nl + nu + n scalars): L below the diagonal by columns (unit diagonal), U above the
 * diagonal by columns, then the diagonal of U. perm: row i of M is row perm[i] of P M; qcol: column
 * j of P M Q is column qcol[j] of M (NULL: Q = I); lp, li / up, ui: column pointers and rows of the
 * strictly lower L / strictly upper U (ascending).
 *
 * x := M^-1 x (trans = 0) or M^-T x (real) / M^-H x (complex) (trans != 0) in place; y: n scalars of
 * work. */
static void LU_SOLVE(int n, const int *perm, const int *qcol, const int *lp, const int *li, const int *up,
                     const int *ui, const LU_T *f, LU_T *x, int trans, LU_T *y)
{
    const int nl = lp[n], nu = up[n];
    const LU_T *L = f, *U = f + nl, *D = U + nu;
    if (!trans) {           /* L U y = P b, x = Q y */
        for (int i = 0; i < n; ++i)
            y[perm[i]] = x[i];
        for (int j = 0; j < n; ++j) {
            const LU_T yj = y[j];
            if (yj != 0.0)
                for (int q = lp[j]; q < lp[j + 1]; ++q)
                    y[li[q]] -= L[q] * yj;
        }
        for (int j = n - 1; j >= 0; --j) {
            const LU_T yj = y[j] / D[j];
            y[j] = yj;
            if (yj != 0.0)
                for (int t = up[j]; t < up[j + 1]; ++t)
                    y[ui[t]] -= U[t] * yj;
        }
        if (qcol)
            for (int j = 0; j < n; ++j)
                x[qcol[j]] = y[j];
        else
            memcpy(x, y, (size_t)n * sizeof(LU_T));
    } else {                /* M^H = Q U^H L^H P: U^H z = Q^T b, L^H w = z, x = P^T w */
        for (int j = 0; j < n; ++j) {
            LU_T s = x[qcol ? qcol[j] : j];
            for (int t = up[j]; t < up[j + 1]; ++t)
                s -= LU_CONJ(U[t]) * y[ui[t]];
            y[j] = s / LU_CONJ(D[j]);
        }
        for (int j = n - 1; j >= 0; --j) {
            LU_T s = y[j];
            for (int q = lp[j]; q < lp[j + 1]; ++q)
                s -= LU_CONJ(L[q]) * y[li[q]];
            y[j] = s;
        }
        for (int i = 0; i < n; ++i)
            x[i] = y[perm[i]];
    }
}
