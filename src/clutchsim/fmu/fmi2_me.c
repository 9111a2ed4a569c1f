/* FMI 2.0 Model Exchange glue of a clutchsim plant (clutchsim/fmu/fmi2_me.c).

   Compiled together with the printed plant (plant.c: cs_rhs, cs_outputs, cs_events,
   cs_reset) and its layout (model.h: sizes, start values, value references, event
   directions, GUID).  The FMI 2.0 types are declared here from the standard's text
   (section 2.1), so the FMU needs no headers but the C library's.

   Value references (all Real): states [0, NX), their derivatives [NX, 2 NX), inputs
   [CS_VR_U, +NU), outputs [CS_VR_Y, +NY), parameters [CS_VR_P, +NP) (the plant's
   parameter vector, in its own order).

   Events.  The plant's event functions are the FMU's event indicators.  At an event
   (fmi2NewDiscreteStates) the first indicator that crossed zero since the last event, in
   the plant's direction (-1 falling, +1 rising, 0 both), gets the plant's reset map, as
   clutchsim's own integrators apply it (one event at a time; the reset map of a switching
   element settles the others it affects: clutchsim's event iteration runs inside it); a
   reset that fails or stops the run terminates the simulation.  "Since the last event":
   the indicators are recorded at the end of initialisation and after each event; an
   importer stops at every sign change (that is what event indicators are for), so between
   two events each keeps its sign.  (Not at fmi2CompletedIntegratorStep: importers call it
   after the step that ends on the root, before the event.) */

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

/* ---------------------------------------------------------------- FMI 2.0 types */
typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef char fmi2Byte;
#define fmi2True 1
#define fmi2False 0

typedef enum { fmi2OK, fmi2Warning, fmi2Discard, fmi2Error, fmi2Fatal, fmi2Pending } fmi2Status;
typedef enum { fmi2ModelExchange, fmi2CoSimulation } fmi2Type;
typedef enum { fmi2DoStepStatus, fmi2PendingStatus, fmi2LastSuccessfulTime, fmi2Terminated } fmi2StatusKind;

typedef void (*fmi2CallbackLogger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String, ...);
typedef void *(*fmi2CallbackAllocateMemory)(size_t, size_t);
typedef void (*fmi2CallbackFreeMemory)(void *);
typedef void (*fmi2StepFinished)(fmi2ComponentEnvironment, fmi2Status);

typedef struct {
    const fmi2CallbackLogger logger;
    const fmi2CallbackAllocateMemory allocateMemory;
    const fmi2CallbackFreeMemory freeMemory;
    const fmi2StepFinished stepFinished;
    const fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;

typedef struct {
    fmi2Boolean newDiscreteStatesNeeded;
    fmi2Boolean terminateSimulation;
    fmi2Boolean nominalsOfContinuousStatesChanged;
    fmi2Boolean valuesOfContinuousStatesChanged;
    fmi2Boolean nextEventTimeDefined;
    fmi2Real nextEventTime;
} fmi2EventInfo;

#if defined(_WIN32)
#define FMI2_EXPORT __declspec(dllexport)
#else
#define FMI2_EXPORT __attribute__((visibility("default")))
#endif

/* ---------------------------------------------------------------- the plant */
void cs_rhs(double t, double *y, double *u, double *p, double *dy);
void cs_outputs(double t, double *y, double *u, double *p, double *out);
void cs_events(double t, double *y, double *u, double *p, double *g);
int cs_reset(double t, double *y, double *u, double *p, int k);

#define ONE(n) ((n) > 0 ? (n) : 1)
enum { ACTION_CONTINUE = 0, ACTION_STATE_CHANGED = 1, ACTION_STOP = 2, ACTION_FAIL = 3 };
enum { MODE_INSTANTIATED, MODE_INIT, MODE_EVENT, MODE_CONT, MODE_TERMINATED };

typedef struct {
    double t;
    double y[ONE(CS_NX)], dy[ONE(CS_NX)], u[ONE(CS_NU)], p[ONE(CS_NP)];
    double out[ONE(CS_NY)], g[ONE(CS_NZ)], g_last[ONE(CS_NZ)];
    int dy_ok, out_ok, mode, logging;
    char *name;
    const fmi2CallbackFunctions *cb;
} Instance;

static void logf_(Instance *m, fmi2Status st, const char *cat, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->cb || !m->cb->logger) return;
    if (st == fmi2OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    m->cb->logger(m->cb->componentEnvironment, m->name, st, cat, "%s", buf);
}

static void changed(Instance *m) { m->dy_ok = 0; m->out_ok = 0; }

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

/* ---------------------------------------------------------------- common functions */
FMI2_EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
FMI2_EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String cats[]) {
    (void)n; (void)cats;
    ((Instance *)c)->logging = on;
    return fmi2OK;
}

FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                          fmi2String resources, const fmi2CallbackFunctions *cb,
                                          fmi2Boolean visible, fmi2Boolean logging) {
    Instance *m;
    (void)resources; (void)visible;
    if (!cb || !cb->allocateMemory || !cb->freeMemory) return NULL;
    if (type != fmi2ModelExchange) {
        if (cb->logger) cb->logger(cb->componentEnvironment, name, fmi2Error, "error",
                                   "this FMU supports Model Exchange only");
        return NULL;
    }
    if (!guid || strcmp(guid, CS_GUID) != 0) {
        if (cb->logger) cb->logger(cb->componentEnvironment, name, fmi2Error, "error",
                                   "wrong GUID %s (expected %s)", guid ? guid : "(null)", CS_GUID);
        return NULL;
    }
    m = (Instance *)cb->allocateMemory(1, sizeof(Instance));
    if (!m) return NULL;
    m->cb = cb;
    m->logging = logging;
    m->name = (char *)cb->allocateMemory(strlen(name ? name : "") + 1, 1);
    if (m->name) strcpy(m->name, name ? name : "");
    memcpy(m->y, cs_y0, sizeof m->y);
    memcpy(m->u, cs_u0, sizeof m->u);
    memcpy(m->p, cs_p0, sizeof m->p);
    m->mode = MODE_INSTANTIATED;
    changed(m);
    return m;
}

FMI2_EXPORT void fmi2FreeInstance(fmi2Component c) {
    Instance *m = (Instance *)c;
    if (!m) return;
    if (m->name) m->cb->freeMemory(m->name);
    m->cb->freeMemory(m);
}

FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                           fmi2Real t0, fmi2Boolean stop_defined, fmi2Real t1) {
    (void)tol_defined; (void)tol; (void)stop_defined; (void)t1;
    ((Instance *)c)->t = t0;
    changed((Instance *)c);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Instance *)c)->mode = MODE_INIT;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *m = (Instance *)c;
    int k;
    changed(m);
    record_signs(m);
    /* a directional event whose function starts on its post-crossing side fires once at
       the start (a stuck element loaded beyond its capacity), as in clutchsim */
    for (k = 0; k < CS_NZ; k++)
        if ((cs_event_dir[k] == -1 && m->g_last[k] < 0.0) || (cs_event_dir[k] == 1 && m->g_last[k] > 0.0))
            m->g_last[k] = -m->g_last[k];
    m->mode = MODE_EVENT;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
    ((Instance *)c)->mode = MODE_TERMINATED;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component c) {
    Instance *m = (Instance *)c;
    memcpy(m->y, cs_y0, sizeof m->y);
    memcpy(m->u, cs_u0, sizeof m->u);
    memcpy(m->p, cs_p0, sizeof m->p);
    m->t = 0.0;
    m->mode = MODE_INSTANTIATED;
    changed(m);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *m = (Instance *)c;
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (r < CS_NX) v[i] = m->y[r];
        else if (r < 2 * CS_NX) { derivatives(m); v[i] = m->dy[r - CS_NX]; }
        else if (r >= CS_VR_U && r < CS_VR_U + CS_NU) v[i] = m->u[r - CS_VR_U];
        else if (r >= CS_VR_Y && r < CS_VR_Y + CS_NY) { outputs(m); v[i] = m->out[r - CS_VR_Y]; }
        else if (r >= CS_VR_P && r < CS_VR_P + CS_NP) v[i] = m->p[r - CS_VR_P];
        else {
            logf_(m, fmi2Error, "error", "fmi2GetReal: unknown value reference %u", r);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    Instance *m = (Instance *)c;
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (r < CS_NX && m->mode != MODE_CONT) m->y[r] = v[i];
        else if (r >= CS_VR_U && r < CS_VR_U + CS_NU) m->u[r - CS_VR_U] = v[i];
        else if (r >= CS_VR_P && r < CS_VR_P + CS_NP && cs_p_settable[r - CS_VR_P]) m->p[r - CS_VR_P] = v[i];
        else {
            logf_(m, fmi2Error, "error", "fmi2SetReal: value reference %u cannot be set%s", r,
                  (r >= CS_VR_P && r < CS_VR_P + CS_NP)
                      ? " (a structural value: an inertia or a ratio; change it in the scenario "
                        "and export again)" : "");
            return fmi2Error;
        }
    }
    changed(m);
    return fmi2OK;
}

#define NO_TYPE(T, CT)                                                                       \
    FMI2_EXPORT fmi2Status fmi2Get##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, CT v[]) { \
        (void)vr; (void)v; if (n == 0) return fmi2OK;                                        \
        logf_((Instance *)c, fmi2Error, "error", "fmi2Get" #T ": the FMU has no such variables"); \
        return fmi2Error; }                                                                   \
    FMI2_EXPORT fmi2Status fmi2Set##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, const CT v[]) { \
        (void)vr; (void)v; if (n == 0) return fmi2OK;                                        \
        logf_((Instance *)c, fmi2Error, "error", "fmi2Set" #T ": the FMU has no such variables"); \
        return fmi2Error; }
NO_TYPE(Integer, fmi2Integer)
NO_TYPE(Boolean, fmi2Boolean)
NO_TYPE(String, fmi2String)

#define UNSUPPORTED(call, args)                                                              \
    FMI2_EXPORT fmi2Status call args {                                                       \
        logf_((Instance *)c, fmi2Error, "error", #call " is not supported by this FMU");     \
        return fmi2Error; }
UNSUPPORTED(fmi2GetFMUstate, (fmi2Component c, fmi2FMUstate *s))
UNSUPPORTED(fmi2SetFMUstate, (fmi2Component c, fmi2FMUstate s))
UNSUPPORTED(fmi2FreeFMUstate, (fmi2Component c, fmi2FMUstate *s))
UNSUPPORTED(fmi2SerializedFMUstateSize, (fmi2Component c, fmi2FMUstate s, size_t *n))
UNSUPPORTED(fmi2SerializeFMUstate, (fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n))
UNSUPPORTED(fmi2DeSerializeFMUstate, (fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s))
UNSUPPORTED(fmi2GetDirectionalDerivative, (fmi2Component c, const fmi2ValueReference u[], size_t nu,
            const fmi2ValueReference z[], size_t nz, const fmi2Real du[], fmi2Real dz[]))
UNSUPPORTED(fmi2SetRealInputDerivatives, (fmi2Component c, const fmi2ValueReference vr[], size_t n,
            const fmi2Integer order[], const fmi2Real v[]))
UNSUPPORTED(fmi2GetRealOutputDerivatives, (fmi2Component c, const fmi2ValueReference vr[], size_t n,
            const fmi2Integer order[], fmi2Real v[]))
UNSUPPORTED(fmi2DoStep, (fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_prior))
UNSUPPORTED(fmi2CancelStep, (fmi2Component c))
UNSUPPORTED(fmi2GetStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Status *v))
UNSUPPORTED(fmi2GetRealStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Real *v))
UNSUPPORTED(fmi2GetIntegerStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Integer *v))
UNSUPPORTED(fmi2GetBooleanStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v))
UNSUPPORTED(fmi2GetStringStatus, (fmi2Component c, const fmi2StatusKind k, fmi2String *v))

/* ---------------------------------------------------------------- model exchange */
FMI2_EXPORT fmi2Status fmi2EnterEventMode(fmi2Component c) {
    ((Instance *)c)->mode = MODE_EVENT;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Instance *m = (Instance *)c;
    double g[ONE(CS_NZ)];
    int k;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    indicators(m, g);
    /* the first indicator that crossed, as clutchsim applies one event at a time (its
       reset map settles every switching element it affects) */
    for (k = 0; k < CS_NZ; k++)
        if (crossed(cs_event_dir[k], m->g_last[k], g[k])) break;
    if (k < CS_NZ) {
        int action = cs_reset(m->t, m->y, m->u, m->p, k);
        changed(m);
        logf_(m, fmi2OK, "events", "t = %.9g s: event %s (%s)", m->t, cs_event_names[k],
              action == ACTION_STATE_CHANGED ? "reset" : action == ACTION_CONTINUE ? "recorded"
              : action == ACTION_STOP ? "stop" : "fail");
        if (action == ACTION_STATE_CHANGED) info->valuesOfContinuousStatesChanged = fmi2True;
        if (action == ACTION_STOP || action == ACTION_FAIL) {
            info->terminateSimulation = fmi2True;
            logf_(m, action == ACTION_FAIL ? fmi2Error : fmi2OK, "events",
                  "t = %.9g s: %s: the run ends here", m->t, cs_event_names[k]);
            m->mode = MODE_TERMINATED;
            return action == ACTION_FAIL ? fmi2Error : fmi2OK;
        }
    }
    record_signs(m);      /* after the reset: the next crossing starts from here */
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    ((Instance *)c)->mode = MODE_CONT;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean no_set_prior,
                                                   fmi2Boolean *enter_event, fmi2Boolean *terminate) {
    (void)c; (void)no_set_prior;
    *enter_event = fmi2False;
    *terminate = fmi2False;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) {
    ((Instance *)c)->t = t;
    changed((Instance *)c);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    Instance *m = (Instance *)c;
    if (n != CS_NX) return fmi2Error;
    memcpy(m->y, x, n * sizeof(double));
    changed(m);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
    Instance *m = (Instance *)c;
    if (n != CS_NX) return fmi2Error;
    derivatives(m);
    memcpy(dx, m->dy, n * sizeof(double));
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real g[], size_t n) {
    Instance *m = (Instance *)c;
    if (n != CS_NZ) return fmi2Error;
    indicators(m, g);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    Instance *m = (Instance *)c;
    if (n != CS_NX) return fmi2Error;
    memcpy(x, m->y, n * sizeof(double));
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    size_t i;
    (void)c;
    for (i = 0; i < n; i++) x[i] = 1.0;
    return fmi2OK;
}
