/* The FMI-independent core of a clutchsim FMU (clutchsim/fmu/plant_core.c), included by
   the FMI 2 and FMI 3 glue (fmi2_me.c, fmi3_me.c).

   It holds one instance of the printed plant (plant.c: cs_rhs, cs_outputs, cs_events,
   cs_reset) with its layout (model.h: sizes, start values, value references, event
   directions, names, the token).

   Value references (all 64-bit floats): states [0, NX), their derivatives [NX, 2 NX),
   inputs [CS_VR_U, +NU), outputs [CS_VR_Y, +NY), parameters [CS_VR_P, +NP) (the plant's
   parameter vector, in its own order), then the event indicators [CS_VR_Z, +NZ) (FMI 3
   names them as variables) and the time CS_VR_T (FMI 3's independent variable).

   Events.  The plant's event functions are the FMU's event indicators.  At an event the
   first indicator that crossed zero since the last event, in the plant's direction (-1
   falling, +1 rising, 0 both), gets the plant's reset map, as clutchsim's own integrators
   apply it (one event at a time; the reset map of a switching element settles the others
   it affects: clutchsim's event iteration runs inside it); a reset that fails or stops the
   run terminates the simulation.  "Since the last event": the indicators are recorded at
   the end of initialisation and after each event; an importer stops at every sign change
   (that is what event indicators are for), so between two events each keeps its sign.
   (Not at the completed integrator step: importers call it after the step that ends on the
   root, before the event.) */

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

void cs_rhs(double t, double *y, double *u, double *p, double *dy);
void cs_outputs(double t, double *y, double *u, double *p, double *out);
void cs_events(double t, double *y, double *u, double *p, double *g);
int cs_reset(double t, double *y, double *u, double *p, int k);
void cs_jac(double t, double *y, double *u, double *p, double *J, int J_nc);

#define ONE(n) ((n) > 0 ? (n) : 1)
#define CS_VR_Z (CS_VR_P + CS_NP)
#define CS_VR_T (CS_VR_Z + CS_NZ)
/* statuses: the same numbers in FMI 2 and FMI 3 */
enum { ST_OK = 0, ST_WARNING = 1, ST_DISCARD = 2, ST_ERROR = 3, ST_FATAL = 4 };
enum { ACTION_CONTINUE = 0, ACTION_STATE_CHANGED = 1, ACTION_STOP = 2, ACTION_FAIL = 3,
       ACTION_PASS = 4 };
enum { MODE_INSTANTIATED, MODE_INIT, MODE_EVENT, MODE_CONT, MODE_TERMINATED };

typedef struct Instance Instance;
typedef void (*core_logger)(Instance *m, int status, const char *category, const char *message);

struct Instance {
    double t;
    double y[ONE(CS_NX)], dy[ONE(CS_NX)], u[ONE(CS_NU)], p[ONE(CS_NP)];
    double out[ONE(CS_NY)], g[ONE(CS_NZ)], g_last[ONE(CS_NZ)];
    int dy_ok, out_ok, mode, logging;
    int cosim;             /* instantiated for co-simulation */
    double rtol, h;        /* co-simulation: the solver's tolerance and its last step */
    /* co-simulation with input derivatives (fmi2SetRealInputDerivatives): within a
       communication step from t_step the inputs are u_step + du·(t − t_step) */
    double du[ONE(CS_NU)], u_step[ONE(CS_NU)], t_step;
    int has_du;
    char *name;
    core_logger log;
    const void *env;       /* the importer's callbacks or environment */
};

static void logf_(Instance *m, int st, const char *cat, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->log) return;
    if (st == ST_OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    m->log(m, st, cat, buf);
}

static void changed(Instance *m) { m->dy_ok = 0; m->out_ok = 0; }

static void core_start(Instance *m) {
    memcpy(m->y, cs_y0, sizeof m->y);
    memcpy(m->u, cs_u0, sizeof m->u);
    memcpy(m->p, cs_p0, sizeof m->p);
    m->t = 0.0;
    m->rtol = 1e-6;
    m->h = 1e-5;
    m->mode = MODE_INSTANTIATED;
    changed(m);
}

static void derivatives(Instance *m) {
    if (!m->dy_ok) {
        memset(m->dy, 0, sizeof m->dy);
        cs_rhs(m->t, m->y, m->u, m->p, m->dy);
        m->dy_ok = 1;
    }
}

static void outputs(Instance *m) {
    if (!m->out_ok) {
        cs_outputs(m->t, m->y, m->u, m->p, m->out);
        m->out_ok = 1;
    }
}

static void indicators(Instance *m, double *g) {
    if (CS_NZ > 0) cs_events(m->t, m->y, m->u, m->p, g);
}

static int crossed(int dir, double before, double now) {
    /* clutchsim.core._driver._crossed */
    return (dir >= 0 && before < 0.0 && now >= 0.0) || (dir <= 0 && before > 0.0 && now <= 0.0);
}

/* The indicators as the reference for the next crossing.  One exactly on zero (a reset
   left it there: a released element's slip) takes the sign it moves to, as clutchsim's
   integrators do ("start from the next sign"): probed a short step along the derivatives. */
static void record_signs(Instance *m) {
    double y1[ONE(CS_NX)], g1[ONE(CS_NZ)], h;
    int k, zero = 0, i;
    indicators(m, m->g_last);
    for (k = 0; k < CS_NZ; k++) zero |= m->g_last[k] == 0.0;
    if (!zero) return;
    derivatives(m);
    h = 1e-9 * (1.0 + fabs(m->t));
    for (i = 0; i < CS_NX; i++) y1[i] = m->y[i] + h * m->dy[i];
    cs_events(m->t + h, y1, m->u, m->p, g1);
    for (k = 0; k < CS_NZ; k++)
        if (m->g_last[k] == 0.0) m->g_last[k] = g1[k];
}

/* End of initialisation: a directional event whose function starts on its post-crossing
   side fires once at the start (a stuck element loaded beyond its capacity), as in
   clutchsim. */
static void core_exit_init(Instance *m) {
    int k;
    changed(m);
    record_signs(m);
    for (k = 0; k < CS_NZ; k++)
        if ((cs_event_dir[k] == -1 && m->g_last[k] < 0.0) || (cs_event_dir[k] == 1 && m->g_last[k] > 0.0))
            m->g_last[k] = -m->g_last[k];
    m->mode = MODE_EVENT;
}

/* One event (see the top of the file); returns the status. */
/* The event iteration at one instant: every event due fires, in turn.  One that crossed
   with the event just fired and is still on its far side after that reset keeps its old
   sign, so that the next pass fires it; the rest start from the values the reset left.
   (Several events are due at one instant at t0 or at an input jump: two clutches that
   both break away when their command drops; with one event per pass the second one's
   crossing was recorded as its new sign and lost.)  At most 2 passes per indicator, as
   the native integrator's own iteration. */
static int core_event(Instance *m, int *values_changed, int *terminate) {
    double g[ONE(CS_NZ)], g_before[ONE(CS_NZ)], keep[ONE(CS_NZ)];
    int pending[ONE(CS_NZ)];
    int k, j, pass, any = 0;
    *values_changed = 0;
    *terminate = 0;
    indicators(m, g);
    for (pass = 0; pass < 2 * CS_NZ + 1; pass++) {
        int action;
        for (k = 0; k < CS_NZ; k++)
            if (crossed(cs_event_dir[k], m->g_last[k], g[k])) break;
        if (k == CS_NZ) break;
        any = 1;
        memcpy(g_before, g, sizeof g);
        action = cs_reset(m->t, m->y, m->u, m->p, k);
        changed(m);
        logf_(m, ST_OK, "events", "t = %.9g s: event %s (%s)", m->t, cs_event_names[k],
              action == ACTION_STATE_CHANGED ? "reset"
              : (action == ACTION_CONTINUE || action == ACTION_PASS) ? "recorded"
              : action == ACTION_STOP ? "stop" : "fail");
        if (action == ACTION_STATE_CHANGED) *values_changed = 1;
        if (action == ACTION_STOP || action == ACTION_FAIL) {
            *terminate = 1;
            logf_(m, action == ACTION_FAIL ? ST_ERROR : ST_OK, "events",
                  "t = %.9g s: %s: the run ends here", m->t, cs_event_names[k]);
            m->mode = MODE_TERMINATED;
            return action == ACTION_FAIL ? ST_ERROR : ST_OK;
        }
        indicators(m, g);
        for (j = 0; j < CS_NZ; j++) {
            pending[j] = j != k && crossed(cs_event_dir[j], m->g_last[j], g_before[j])
                         && crossed(cs_event_dir[j], m->g_last[j], g[j]);
            keep[j] = m->g_last[j];
        }
        record_signs(m);  /* after the reset: the next crossing starts from here ... */
        for (j = 0; j < CS_NZ; j++)
            if (pending[j]) m->g_last[j] = keep[j];   /* ... but for the pending ones */
    }
    if (!any) record_signs(m);
    return ST_OK;
}

static int core_get(Instance *m, const unsigned vr[], size_t n, double v[], const char *fn) {
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (r < CS_NX) v[i] = m->y[r];
        else if (r < 2 * CS_NX) { derivatives(m); v[i] = m->dy[r - CS_NX]; }
        else if (r >= CS_VR_U && r < CS_VR_U + CS_NU) v[i] = m->u[r - CS_VR_U];
        else if (r >= CS_VR_Y && r < CS_VR_Y + CS_NY) { outputs(m); v[i] = m->out[r - CS_VR_Y]; }
        else if (r >= CS_VR_P && r < CS_VR_P + CS_NP) v[i] = m->p[r - CS_VR_P];
        else if (r >= CS_VR_Z && r < CS_VR_Z + CS_NZ) { indicators(m, m->g); v[i] = m->g[r - CS_VR_Z]; }
        else if (r == CS_VR_T) v[i] = m->t;
        else {
            logf_(m, ST_ERROR, "error", "%s: unknown value reference %u", fn, r);
            return ST_ERROR;
        }
    }
    return ST_OK;
}

static int core_set(Instance *m, const unsigned vr[], size_t n, const double v[], const char *fn) {
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (r < CS_NX && m->mode != MODE_CONT) m->y[r] = v[i];
        else if (r >= CS_VR_U && r < CS_VR_U + CS_NU) m->u[r - CS_VR_U] = v[i];
        else if (r >= CS_VR_P && r < CS_VR_P + CS_NP && cs_p_settable[r - CS_VR_P]) m->p[r - CS_VR_P] = v[i];
        else {
            logf_(m, ST_ERROR, "error", "%s: value reference %u cannot be set%s", fn, r,
                  (r >= CS_VR_P && r < CS_VR_P + CS_NP)
                      ? " (a structural value: an inertia or a ratio; change it in the scenario "
                        "and export again)" : "");
            return ST_ERROR;
        }
    }
    changed(m);
    return ST_OK;
}

/* The importer's states (fmi2SetContinuousStates, fmi3SetContinuousStates: continuous-time
   mode).  The discrete ones (cs_discrete: a switching element's mode, its lock flag, a
   counter) keep the values the last event left: their derivative is 0, so an importer's
   integrator moves them only by round-off, and the plant reads them exactly (a mode of
   1e-51 is not the engaged mode 0).  CVode's difference-quotient Jacobian perturbs each
   state in turn; its Newton corrector then carried +-1e-51 into the elastic dog's mode,
   which opened the teeth and fired "engage" at every step (examples/dog_backlash.toml:
   millions of events at t = 5 ms, docs/fmu.md).  Kept here, the perturbed column is 0, as
   the plant's exact Jacobian has it. */
static int core_set_states(Instance *m, const double x[], size_t n) {
    size_t i;
    if (n != CS_NX) return ST_ERROR;
    for (i = 0; i < n; i++)
        if (!cs_discrete[i]) m->y[i] = x[i];
    changed(m);
    return ST_OK;
}

static int core_get_states(Instance *m, double x[], size_t n) {
    if (n != CS_NX) return ST_ERROR;
    memcpy(x, m->y, n * sizeof(double));
    return ST_OK;
}

static int core_get_derivatives(Instance *m, double dx[], size_t n) {
    if (n != CS_NX) return ST_ERROR;
    derivatives(m);
    memcpy(dx, m->dy, n * sizeof(double));
    return ST_OK;
}

static int core_get_indicators(Instance *m, double g[], size_t n) {
    if (n != CS_NZ) return ST_ERROR;
    indicators(m, g);
    return ST_OK;
}

static void core_nominals(double x[], size_t n) {
    size_t i;
    for (i = 0; i < n; i++) x[i] = 1.0;
}

/* ---------------------------------------------------------------- directional derivatives
   sens = (d unknowns / d knowns) seed (FMI 2 fmi2GetDirectionalDerivative, FMI 3
   fmi3GetDirectionalDerivative).  Knowns: states, inputs, tunable parameters, the time
   (FMI 3's independent variable).  Unknowns:
   the states' derivatives, the states (as outputs), the output signals.
   - The derivatives with respect to the states: the plant's exact Jacobian (cs_jac).
   - The states with respect to the knowns: the seed of the state itself (exact).
   - The derivatives with respect to inputs, parameters and time, and the output signals: a
     fourth-order central difference along the seed in the FMU (the plant has no exact
     Jacobian for them), step 1e-5 of the moved values (relative error about 1e-10). */

#define DD_STEP 1e-5

/* rhs (outs = 0) or outputs (outs = 1) at the instance's point moved by
   s * (dx, du, dp, dt) */
static void dd_eval(Instance *m, int outs, double s, const double *dx, const double *du,
                    const double *dp, double dt, double *res) {
    double y[ONE(CS_NX)], u[ONE(CS_NU)], p[ONE(CS_NP)];
    int i;
    for (i = 0; i < CS_NX; i++) y[i] = m->y[i] + s * dx[i];
    for (i = 0; i < CS_NU; i++) u[i] = m->u[i] + s * du[i];
    for (i = 0; i < CS_NP; i++) p[i] = m->p[i] + s * dp[i];
    if (outs) cs_outputs(m->t + s * dt, y, u, p, res);
    else {
        memset(res, 0, CS_NX * sizeof(double));
        cs_rhs(m->t + s * dt, y, u, p, res);
    }
}

/* the step of a central difference along (dx, du, dp): DD_STEP of each moved value (at most) */
static double dd_step(Instance *m, const double *dx, const double *du, const double *dp,
                      double dt) {
    double s = dt != 0.0 ? (1.0 + fabs(m->t)) / fabs(dt) : HUGE_VAL;
    int i;
    for (i = 0; i < CS_NX; i++) if (dx[i] != 0.0) s = fmin(s, (1.0 + fabs(m->y[i])) / fabs(dx[i]));
    for (i = 0; i < CS_NU; i++) if (du[i] != 0.0) s = fmin(s, (1.0 + fabs(m->u[i])) / fabs(du[i]));
    for (i = 0; i < CS_NP; i++) if (dp[i] != 0.0) s = fmin(s, (1.0 + fabs(m->p[i])) / fabs(dp[i]));
    return s == HUGE_VAL ? 0.0 : DD_STEP * s;
}

/* the fourth-order central difference (Richardson's): (8 (f(s) - f(-s)) - (f(2s) - f(-2s))) / 12 s;
   the friction laws' steep slip transitions make a second-order one's error reach 1e-6 */
static void dd_central(Instance *m, int outs, const double *dx, const double *du, const double *dp,
                       double dt, double *res, int n) {
    double a[ONE(CS_NX + CS_NY)], b[ONE(CS_NX + CS_NY)], c[ONE(CS_NX + CS_NY)];
    double d[ONE(CS_NX + CS_NY)], s = dd_step(m, dx, du, dp, dt);
    int i;
    if (s == 0.0) { memset(res, 0, n * sizeof(double)); return; }
    dd_eval(m, outs, s, dx, du, dp, dt, a);
    dd_eval(m, outs, -s, dx, du, dp, dt, b);
    dd_eval(m, outs, 2.0 * s, dx, du, dp, dt, c);
    dd_eval(m, outs, -2.0 * s, dx, du, dp, dt, d);
    for (i = 0; i < n; i++) res[i] = (8.0 * (a[i] - b[i]) - (c[i] - d[i])) / (12.0 * s);
}

static int core_directional(Instance *m, const unsigned unk[], size_t n_unk, const unsigned kn[],
                            size_t n_kn, const double seed[], double sens[], const char *fn) {
    enum { N = ONE(CS_NX) };
    double dx[N], du[ONE(CS_NU)], dp[ONE(CS_NP)], zero[N], J[N * N];
    double drhs[N], dout[ONE(CS_NY)], dt = 0.0;
    int have_j = 0, have_rhs = 0, have_out = 0, other = 0;
    size_t i;
    memset(dx, 0, sizeof dx); memset(du, 0, sizeof du); memset(dp, 0, sizeof dp);
    memset(zero, 0, sizeof zero);
    for (i = 0; i < n_kn; i++) {
        unsigned r = kn[i];
        if (r < CS_NX) dx[r] += seed[i];
        else if (r >= CS_VR_U && r < CS_VR_U + CS_NU) { du[r - CS_VR_U] += seed[i]; other |= seed[i] != 0.0; }
        else if (r >= CS_VR_P && r < CS_VR_P + CS_NP && cs_p_settable[r - CS_VR_P]) {
            dp[r - CS_VR_P] += seed[i]; other |= seed[i] != 0.0;
        } else if (r == CS_VR_T) { dt += seed[i]; other |= seed[i] != 0.0; }
        else {
            logf_(m, ST_ERROR, "error", "%s: value reference %u is not a known (a state, an "
                  "input, a tunable parameter or the time)", fn, r);
            return ST_ERROR;
        }
    }
    for (i = 0; i < n_unk; i++) {
        unsigned r = unk[i];
        if (r < CS_NX) sens[i] = dx[r];
        else if (r < 2 * CS_NX) {
            int k = (int)(r - CS_NX), j;
            if (!have_j) {
                memset(J, 0, sizeof J);
                cs_jac(m->t, m->y, m->u, m->p, J, CS_NX);
                have_j = 1;
            }
            if (other && !have_rhs) { dd_central(m, 0, zero, du, dp, dt, drhs, CS_NX); have_rhs = 1; }
            sens[i] = other ? drhs[k] : 0.0;
            for (j = 0; j < CS_NX; j++) sens[i] += J[k * CS_NX + j] * dx[j];
        } else if (r >= CS_VR_Y && r < CS_VR_Y + CS_NY) {
            if (!have_out) { dd_central(m, 1, dx, du, dp, dt, dout, CS_NY); have_out = 1; }
            sens[i] = dout[r - CS_VR_Y];
        } else {
            logf_(m, ST_ERROR, "error", "%s: value reference %u is not an unknown (a state, a "
                  "derivative or an output)", fn, r);
            return ST_ERROR;
        }
    }
    return ST_OK;
}
