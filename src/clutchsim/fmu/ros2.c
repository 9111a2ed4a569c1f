/* One step of ROS2 (clutchsim/fmu/ros2.c), the one Rosenbrock step of clutchsim's C code:
   the co-simulation FMU's variable-step solver (rosenbrock.c) and the fixed-step real-time
   kernel (rt_kernel.c) both take their steps here.

   ROS2 (Verwer, Spee, Blom, Hundsdorfer 1999: "A second-order Rosenbrock method applied to
   photochemical dispersion problems", SIAM J. Sci. Comput. 20(4)), L-stable, with the
   plant's exact Jacobian (cs_jac) and its embedded first-order solution for the error:

       (I - g h J) k1 = f(y)
       (I - g h J) k2 = f(y + h k1) - 2 k1,          g = 1 + 1/sqrt(2)
       y1 = y + 3/2 h k1 + 1/2 h k2,                  error = y1 - (y + h k1)

   The work of a step is fixed: one Jacobian, one LU factorisation with partial pivoting
   (n^3/3 multiply-adds), two right-hand sides and two triangular solves; no allocation
   (the arrays are on the stack, sized by model.h), no recursion, no I/O.  The inputs are
   held over the step. */

#define RB_G 1.7071067811865475     /* 1 + 1/sqrt(2) */

/* LU with partial pivoting of the n x n row-major a, in place; 0 if singular */
static int rb_lu(double *a, int *piv, int n) {
    int i, j, k;
    for (k = 0; k < n; k++) {
        int pk = k;
        double big = fabs(a[k * n + k]);
        for (i = k + 1; i < n; i++)
            if (fabs(a[i * n + k]) > big) { big = fabs(a[i * n + k]); pk = i; }
        if (big == 0.0) return 0;
        piv[k] = pk;
        if (pk != k)
            for (j = 0; j < n; j++) { double s = a[k * n + j]; a[k * n + j] = a[pk * n + j]; a[pk * n + j] = s; }
        for (i = k + 1; i < n; i++) {
            double f = a[i * n + k] / a[k * n + k];
            a[i * n + k] = f;
            for (j = k + 1; j < n; j++) a[i * n + j] -= f * a[k * n + j];
        }
    }
    return 1;
}

static void rb_solve(const double *a, const int *piv, int n, double *b) {
    int i, j;
    for (i = 0; i < n; i++) {
        double s;
        if (piv[i] != i) { s = b[i]; b[i] = b[piv[i]]; b[piv[i]] = s; }
    }
    for (i = 0; i < n; i++)
        for (j = 0; j < i; j++) b[i] -= a[i * n + j] * b[j];
    for (i = n - 1; i >= 0; i--) {
        for (j = i + 1; j < n; j++) b[i] -= a[i * n + j] * b[j];
        b[i] /= a[i * n + i];
    }
}

/* One ROS2 step of size h from (t, y0) with inputs u and parameters p into y1 (and the
   error estimate into err); 0 if the matrix is singular or a value is not finite.  du
   (NULL: inputs held): the inputs' slopes, so the second stage, at t + h, reads u + h·du.
   ROS2 is a W-method, second order with any matrix in place of the Jacobian, so the
   missing ∂f/∂t column (time as a state) costs no order. */
static int ros2_step(double t, const double *y0, double *u, const double *du, double *p,
                     double h, double *y1, double *err) {
    enum { N = ONE(CS_NX), U = ONE(CS_NU) };
    double J[N * N], A[N * N], k1[N], k2[N], yt[N], f[N], u2[U], *ub = u;
    int piv[N], i, j, n = CS_NX;
    if (du != NULL) {
        for (i = 0; i < CS_NU; i++) u2[i] = u[i] + h * du[i];
        ub = u2;
    }
    memcpy(yt, y0, sizeof yt);
    memset(J, 0, sizeof J);
    cs_jac(t, yt, u, p, J, n);
    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) A[i * n + j] = (i == j ? 1.0 : 0.0) - RB_G * h * J[i * n + j];
    if (!rb_lu(A, piv, n)) return 0;
    memset(k1, 0, sizeof k1);
    cs_rhs(t, yt, u, p, k1);
    rb_solve(A, piv, n, k1);
    for (i = 0; i < n; i++) yt[i] = y0[i] + h * k1[i];
    memset(f, 0, sizeof f);
    cs_rhs(t + h, yt, ub, p, f);
    for (i = 0; i < n; i++) k2[i] = f[i] - 2.0 * k1[i];
    rb_solve(A, piv, n, k2);
    for (i = 0; i < n; i++) {
        y1[i] = y0[i] + 1.5 * h * k1[i] + 0.5 * h * k2[i];
        err[i] = 0.5 * h * (k1[i] + k2[i]);
        if (!isfinite(y1[i])) return 0;
    }
    return 1;
}

