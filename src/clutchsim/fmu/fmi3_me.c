/* FMI 3.0 glue of a clutchsim FMU (clutchsim/fmu/fmi3_me.c): Model Exchange and, where
   model.h says so (CS_COSIM), co-simulation without event mode with the internal solver of
   rosenbrock.c (the same as FMI 2's); over the FMI-independent core plant_core.c (value
   references, events, directional derivatives: see there) and the functions both versions
   share (fmi_common.c).  The FMI 3.0 types are declared here from the standard's text
   (section 2.2), so the FMU needs no headers but the C library's.  Only Float64 variables exist; the event indicators are
   variables too (value references [CS_VR_Z, +NZ)). */

#include <stdbool.h>
#include <stdint.h>

#include "plant_core.c"
#include "rosenbrock.c"

typedef void *fmi3Instance;
typedef void *fmi3InstanceEnvironment;
typedef void *fmi3FMUState;
typedef uint32_t fmi3ValueReference;
typedef float fmi3Float32;
typedef double fmi3Float64;
typedef int8_t fmi3Int8;
typedef uint8_t fmi3UInt8;
typedef int16_t fmi3Int16;
typedef uint16_t fmi3UInt16;
typedef int32_t fmi3Int32;
typedef uint32_t fmi3UInt32;
typedef int64_t fmi3Int64;
typedef uint64_t fmi3UInt64;
typedef bool fmi3Boolean;
typedef char fmi3Char;
typedef const fmi3Char *fmi3String;
typedef uint8_t fmi3Byte;
typedef const fmi3Byte *fmi3Binary;
typedef bool fmi3Clock;

typedef enum { fmi3OK, fmi3Warning, fmi3Discard, fmi3Error, fmi3Fatal } fmi3Status;
typedef enum { fmi3Independent, fmi3Constant, fmi3Fixed, fmi3Tunable, fmi3Discrete,
               fmi3Dependent } fmi3DependencyKind;
typedef enum { fmi3IntervalNotYetKnown, fmi3IntervalUnchanged, fmi3IntervalChanged } fmi3IntervalQualifier;
typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String);

#if defined(_WIN32)
#define FMI3_EXPORT __declspec(dllexport)
#else
#define FMI3_EXPORT __attribute__((visibility("default")))
#endif

typedef struct {
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} Env3;

static void log_fmi3(Instance *m, int st, const char *cat, const char *msg) {
    const Env3 *e = (const Env3 *)m->env;
    if (e && e->log) e->log(e->env, (fmi3Status)st, cat, msg);
}

#define M ((Instance *)instance)

#define FMI_FN(name) fmi3##name
#define FMI_EXPORT FMI3_EXPORT
#define FMI_INSTANCE fmi3Instance
#define FMI_STATUS fmi3Status
#define FMI_BOOLEAN fmi3Boolean
#define FMI_STRING fmi3String
#define FMI_TRUE true
#define FMI_FALSE false
#define FMI_GET_DERIVATIVES fmi3GetContinuousStateDerivatives
#include "fmi_common.c"

static fmi3Instance instantiate(fmi3String name, fmi3String token, fmi3Boolean logging,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback log, int cosim) {
    Instance *m;
    Env3 *e;
    if (!token || strcmp(token, CS_GUID) != 0) {
        if (log) log(env, fmi3Error, "error", "wrong instantiation token");
        return NULL;
    }
    if ((cosim && !CS_COSIM) || (!cosim && !CS_MODEL_EXCHANGE)) {
        if (log) log(env, fmi3Error, "error", cosim ? "this FMU is for Model Exchange only"
                                                    : "this FMU is for co-simulation only");
        return NULL;
    }
    m = (Instance *)calloc(1, sizeof(Instance));
    e = (Env3 *)calloc(1, sizeof(Env3));
    if (!m || !e) { free(m); free(e); return NULL; }
    e->env = env;
    e->log = log;
    m->env = e;
    m->log = log_fmi3;
    m->logging = logging;
    m->name = (char *)calloc(strlen(name ? name : "") + 1, 1);
    if (m->name) strcpy(m->name, name ? name : "");
    core_start(m);
    m->cosim = cosim;
    return m;
}

/* ---------------------------------------------------------------- common functions */
FMI3_EXPORT const char *fmi3GetVersion(void) { return "3.0"; }

FMI3_EXPORT fmi3Instance fmi3InstantiateModelExchange(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging, fmi3InstanceEnvironment env, fmi3LogMessageCallback log) {
    (void)resources; (void)visible;
    return instantiate(name, token, logging, env, log, 0);
}

/* Co-simulation without event mode (hasEventMode="false"): the FMU handles its events
   inside fmi3DoStep, with its own solver (rosenbrock.c), as the FMI 2 co-simulation does.
   It does not return early and has no intermediate update. */
FMI3_EXPORT fmi3Instance fmi3InstantiateCoSimulation(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early_return,
        const fmi3ValueReference req[], size_t n_req, fmi3InstanceEnvironment env,
        fmi3LogMessageCallback log, void *intermediate_update) {
    (void)resources; (void)visible; (void)early_return; (void)req; (void)n_req;
    (void)intermediate_update;
    if (event_mode) {
        if (log) log(env, fmi3Error, "error", "this FMU has no event mode (hasEventMode=false): "
                     "it handles its events inside fmi3DoStep");
        return NULL;
    }
    return instantiate(name, token, logging, env, log, 1);
}

FMI3_EXPORT fmi3Instance fmi3InstantiateScheduledExecution(
        fmi3String name, fmi3String token, fmi3String resources, fmi3Boolean visible,
        fmi3Boolean logging, fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
        void *clock_update, void *lock, void *unlock) {
    (void)name; (void)token; (void)resources; (void)visible; (void)logging;
    (void)clock_update; (void)lock; (void)unlock;
    if (log) log(env, fmi3Error, "error", "this FMU supports Model Exchange only");
    return NULL;
}

FMI3_EXPORT void fmi3FreeInstance(fmi3Instance instance) {
    if (!instance) return;
    free(M->name);
    free((void *)M->env);
    free(M);
}

FMI3_EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean tol_defined,
                                                   fmi3Float64 tol, fmi3Float64 t0,
                                                   fmi3Boolean stop_defined, fmi3Float64 t1) {
    (void)stop_defined; (void)t1;
    if (tol_defined && tol > 0.0) M->rtol = tol;      /* co-simulation: the solver's tolerance */
    M->t = t0;
    M->mode = MODE_INIT;
    changed(M);
    return fmi3OK;
}

FMI3_EXPORT fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                      fmi3Float64 v[], size_t nv) {
    if (nv != nvr) return fmi3Error;
    return (fmi3Status)core_get(M, vr, nvr, v, "fmi3GetFloat64");
}

FMI3_EXPORT fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                      const fmi3Float64 v[], size_t nv) {
    if (nv != nvr) return fmi3Error;
    return (fmi3Status)core_set(M, vr, nvr, v, "fmi3SetFloat64");
}

/* every other type: this FMU has no such variables */
#define NO_TYPE(T, CT)                                                                       \
    FMI3_EXPORT fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, \
                                      CT v[], size_t nv) {                                    \
        (void)vr; (void)v; (void)nv; if (nvr == 0) return fmi3OK;                            \
        logf_(M, ST_ERROR, "error", "fmi3Get" #T ": the FMU has no such variables");         \
        return fmi3Error; }                                                                   \
    FMI3_EXPORT fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, \
                                      const CT v[], size_t nv) {                              \
        (void)vr; (void)v; (void)nv; if (nvr == 0) return fmi3OK;                            \
        logf_(M, ST_ERROR, "error", "fmi3Set" #T ": the FMU has no such variables");         \
        return fmi3Error; }
NO_TYPE(Float32, fmi3Float32)
NO_TYPE(Int8, fmi3Int8)
NO_TYPE(UInt8, fmi3UInt8)
NO_TYPE(Int16, fmi3Int16)
NO_TYPE(UInt16, fmi3UInt16)
NO_TYPE(Int32, fmi3Int32)
NO_TYPE(UInt32, fmi3UInt32)
NO_TYPE(Int64, fmi3Int64)
NO_TYPE(UInt64, fmi3UInt64)
NO_TYPE(Boolean, fmi3Boolean)
NO_TYPE(String, fmi3String)

#define UNSUPPORTED(call, args)                                                              \
    FMI3_EXPORT fmi3Status call args {                                                       \
        logf_(M, ST_ERROR, "error", #call " is not supported by this FMU");                  \
        return fmi3Error; }
UNSUPPORTED(fmi3GetBinary, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            size_t sizes[], fmi3Binary v[], size_t nv))
UNSUPPORTED(fmi3SetBinary, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const size_t sizes[], const fmi3Binary v[], size_t nv))
UNSUPPORTED(fmi3GetClock, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]))
UNSUPPORTED(fmi3SetClock, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock v[]))
UNSUPPORTED(fmi3GetNumberOfVariableDependencies, (fmi3Instance instance, fmi3ValueReference vr, size_t *n))
UNSUPPORTED(fmi3GetVariableDependencies, (fmi3Instance instance, fmi3ValueReference dep,
            size_t idx_dep[], fmi3ValueReference ind[], size_t idx_ind[], fmi3DependencyKind kinds[],
            size_t n))
UNSUPPORTED(fmi3GetFMUState, (fmi3Instance instance, fmi3FMUState *s))
UNSUPPORTED(fmi3SetFMUState, (fmi3Instance instance, fmi3FMUState s))
UNSUPPORTED(fmi3FreeFMUState, (fmi3Instance instance, fmi3FMUState *s))
UNSUPPORTED(fmi3SerializedFMUStateSize, (fmi3Instance instance, fmi3FMUState s, size_t *n))
UNSUPPORTED(fmi3SerializeFMUState, (fmi3Instance instance, fmi3FMUState s, fmi3Byte b[], size_t n))
UNSUPPORTED(fmi3DeserializeFMUState, (fmi3Instance instance, const fmi3Byte b[], size_t n, fmi3FMUState *s))
UNSUPPORTED(fmi3EnterConfigurationMode, (fmi3Instance instance))
UNSUPPORTED(fmi3ExitConfigurationMode, (fmi3Instance instance))
UNSUPPORTED(fmi3GetIntervalDecimal, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            fmi3Float64 iv[], fmi3IntervalQualifier q[]))
UNSUPPORTED(fmi3GetIntervalFraction, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            fmi3UInt64 c[], fmi3UInt64 r[], fmi3IntervalQualifier q[]))
UNSUPPORTED(fmi3GetShiftDecimal, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            fmi3Float64 s[]))
UNSUPPORTED(fmi3GetShiftFraction, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            fmi3UInt64 c[], fmi3UInt64 r[]))
UNSUPPORTED(fmi3SetIntervalDecimal, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const fmi3Float64 iv[]))
UNSUPPORTED(fmi3SetIntervalFraction, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const fmi3UInt64 c[], const fmi3UInt64 r[]))
UNSUPPORTED(fmi3SetShiftDecimal, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const fmi3Float64 s[]))
UNSUPPORTED(fmi3SetShiftFraction, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const fmi3UInt64 c[], const fmi3UInt64 r[]))
UNSUPPORTED(fmi3GetOutputDerivatives, (fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
            const fmi3Int32 orders[], fmi3Float64 v[], size_t nv))
UNSUPPORTED(fmi3ActivateModelPartition, (fmi3Instance instance, fmi3ValueReference clock, fmi3Float64 t))

FMI3_EXPORT fmi3Status fmi3GetDirectionalDerivative(
        fmi3Instance instance, const fmi3ValueReference unk[], size_t n_unk,
        const fmi3ValueReference kn[], size_t n_kn, const fmi3Float64 seed[], size_t n_seed,
        fmi3Float64 sens[], size_t n_sens) {
    if (n_seed != n_kn || n_sens != n_unk) return fmi3Error;
    return (fmi3Status)core_directional(M, unk, n_unk, kn, n_kn, seed, sens,
                                        "fmi3GetDirectionalDerivative");
}

/* FMI 3 fmi3GetAdjointDerivative: sens = seed^T (d unknowns / d knowns), column by column
   with core_directional (so with the same exact and differenced parts). */
static int adjoint(Instance *m, const unsigned unk[], size_t n_unk, const unsigned kn[],
                        size_t n_kn, const double seed[], double sens[], const char *fn) {
    double col[ONE(2 * CS_NX + CS_NY)], one = 1.0;
    size_t i, j;
    if (n_unk > ONE(2 * CS_NX + CS_NY)) {
        logf_(m, ST_ERROR, "error", "%s: %u unknowns, more than the FMU has", fn, (unsigned)n_unk);
        return ST_ERROR;
    }
    for (j = 0; j < n_kn; j++) {
        int st = core_directional(m, unk, n_unk, &kn[j], 1, &one, col, fn);
        if (st != ST_OK) return st;
        sens[j] = 0.0;
        for (i = 0; i < n_unk; i++) sens[j] += seed[i] * col[i];
    }
    return ST_OK;
}

FMI3_EXPORT fmi3Status fmi3GetAdjointDerivative(
        fmi3Instance instance, const fmi3ValueReference unk[], size_t n_unk,
        const fmi3ValueReference kn[], size_t n_kn, const fmi3Float64 seed[], size_t n_seed,
        fmi3Float64 sens[], size_t n_sens) {
    if (n_seed != n_unk || n_sens != n_kn) return fmi3Error;
    return (fmi3Status)adjoint(M, unk, n_unk, kn, n_kn, seed, sens, "fmi3GetAdjointDerivative");
}

/* ---------------------------------------------------------------- co-simulation */
FMI3_EXPORT fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    M->mode = MODE_CONT;
    return fmi3OK;
}

FMI3_EXPORT fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 t, fmi3Float64 h,
                                  fmi3Boolean no_prior, fmi3Boolean *event_needed,
                                  fmi3Boolean *terminate, fmi3Boolean *early, fmi3Float64 *last) {
    int st;
    (void)no_prior;
    st = rb_do_step(M, t, h, "fmi3DoStep");
    *event_needed = false;
    *early = false;
    *last = M->t;
    *terminate = st == ST_DISCARD || st == ST_ERROR;
    /* a terminal stop ends the run where it happened (lastSuccessfulTime) */
    return st == ST_DISCARD ? fmi3OK : (fmi3Status)st;
}

FMI3_EXPORT fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    (void)instance;
    return fmi3OK;
}

FMI3_EXPORT fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *need_update,
                                                fmi3Boolean *terminate, fmi3Boolean *nominals_changed,
                                                fmi3Boolean *values_changed,
                                                fmi3Boolean *next_time_defined, fmi3Float64 *next_time) {
    int vc, term, st;
    st = core_event(M, &vc, &term);
    *need_update = false;
    *terminate = term != 0;
    *nominals_changed = false;
    *values_changed = vc != 0;
    *next_time_defined = false;
    *next_time = 0.0;
    return (fmi3Status)st;
}

/* ---------------------------------------------------------------- model exchange */
FMI3_EXPORT fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n) {
    (void)instance;
    *n = CS_NZ;
    return fmi3OK;
}

FMI3_EXPORT fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n) {
    (void)instance;
    *n = CS_NX;
    return fmi3OK;
}
