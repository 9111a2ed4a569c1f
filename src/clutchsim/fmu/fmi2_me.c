/* FMI 2.0 glue of a clutchsim FMU (clutchsim/fmu/fmi2_me.c): Model Exchange and, where
   model.h says so (CS_COSIM), co-simulation with the internal solver of rosenbrock.c;
   over the FMI-independent core plant_core.c (value references, events: see there).  The FMI 2.0
   types are declared here from the standard's text (section 2.1), so the FMU needs no
   headers but the C library's. */

#include "plant_core.c"
#include "rosenbrock.c"

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

#define FMI_FN(name) fmi2##name
#define FMI_EXPORT FMI2_EXPORT
#define FMI_INSTANCE fmi2Component
#define FMI_STATUS fmi2Status
#define FMI_BOOLEAN fmi2Boolean
#define FMI_STRING fmi2String
#define FMI_TRUE fmi2True
#define FMI_FALSE fmi2False
#define FMI_GET_DERIVATIVES fmi2GetDerivatives
#include "fmi_common.c"

static void log_fmi2(Instance *m, int st, const char *cat, const char *msg) {
    const fmi2CallbackFunctions *cb = (const fmi2CallbackFunctions *)m->env;
    if (cb && cb->logger) cb->logger(cb->componentEnvironment, m->name, (fmi2Status)st, cat, "%s", msg);
}

/* ---------------------------------------------------------------- common functions */
FMI2_EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
FMI2_EXPORT const char *fmi2GetVersion(void) { return "2.0"; }

FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid,
                                          fmi2String resources, const fmi2CallbackFunctions *cb,
                                          fmi2Boolean visible, fmi2Boolean logging) {
    Instance *m;
    (void)resources; (void)visible;
    if (!cb || !cb->allocateMemory || !cb->freeMemory) return NULL;
    if ((type == fmi2ModelExchange && !CS_MODEL_EXCHANGE) || (type == fmi2CoSimulation && !CS_COSIM)) {
        if (cb->logger) cb->logger(cb->componentEnvironment, name, fmi2Error, "error",
                                   type == fmi2CoSimulation ? "this FMU is for Model Exchange only"
                                                            : "this FMU is for co-simulation only");
        return NULL;
    }
    if (!guid || strcmp(guid, CS_GUID) != 0) {
        if (cb->logger) cb->logger(cb->componentEnvironment, name, fmi2Error, "error",
                                   "wrong GUID %s (expected %s)", guid ? guid : "(null)", CS_GUID);
        return NULL;
    }
    m = (Instance *)cb->allocateMemory(1, sizeof(Instance));
    if (!m) return NULL;
    m->env = cb;
    m->log = log_fmi2;
    m->logging = logging;
    m->name = (char *)cb->allocateMemory(strlen(name ? name : "") + 1, 1);
    if (m->name) strcpy(m->name, name ? name : "");
    core_start(m);
    m->cosim = type == fmi2CoSimulation;
    return m;
}

FMI2_EXPORT void fmi2FreeInstance(fmi2Component c) {
    Instance *m = (Instance *)c;
    const fmi2CallbackFunctions *cb;
    if (!m) return;
    cb = (const fmi2CallbackFunctions *)m->env;
    if (m->name) cb->freeMemory(m->name);
    cb->freeMemory(m);
}

FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_defined, fmi2Real tol,
                                           fmi2Real t0, fmi2Boolean stop_defined, fmi2Real t1) {
    (void)stop_defined; (void)t1;
    if (tol_defined && tol > 0.0) ((Instance *)c)->rtol = tol;
    ((Instance *)c)->t = t0;
    changed((Instance *)c);
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Instance *)c)->mode = MODE_INIT;
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    return (fmi2Status)core_get((Instance *)c, vr, n, v, "fmi2GetReal");
}

FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, const fmi2Real v[]) {
    return (fmi2Status)core_set((Instance *)c, vr, n, v, "fmi2SetReal");
}

#define NO_TYPE(T, CT)                                                                       \
    FMI2_EXPORT fmi2Status fmi2Get##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, CT v[]) { \
        (void)vr; (void)v; if (n == 0) return fmi2OK;                                        \
        logf_((Instance *)c, ST_ERROR, "error", "fmi2Get" #T ": the FMU has no such variables"); \
        return fmi2Error; }                                                                   \
    FMI2_EXPORT fmi2Status fmi2Set##T(fmi2Component c, const fmi2ValueReference vr[], size_t n, const CT v[]) { \
        (void)vr; (void)v; if (n == 0) return fmi2OK;                                        \
        logf_((Instance *)c, ST_ERROR, "error", "fmi2Set" #T ": the FMU has no such variables"); \
        return fmi2Error; }
NO_TYPE(Integer, fmi2Integer)
NO_TYPE(Boolean, fmi2Boolean)
NO_TYPE(String, fmi2String)

#define UNSUPPORTED(call, args)                                                              \
    FMI2_EXPORT fmi2Status call args {                                                       \
        logf_((Instance *)c, ST_ERROR, "error", #call " is not supported by this FMU");     \
        return fmi2Error; }
UNSUPPORTED(fmi2GetFMUstate, (fmi2Component c, fmi2FMUstate *s))
UNSUPPORTED(fmi2SetFMUstate, (fmi2Component c, fmi2FMUstate s))
UNSUPPORTED(fmi2FreeFMUstate, (fmi2Component c, fmi2FMUstate *s))
UNSUPPORTED(fmi2SerializedFMUstateSize, (fmi2Component c, fmi2FMUstate s, size_t *n))
UNSUPPORTED(fmi2SerializeFMUstate, (fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n))
UNSUPPORTED(fmi2DeSerializeFMUstate, (fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s))
UNSUPPORTED(fmi2GetRealOutputDerivatives, (fmi2Component c, const fmi2ValueReference vr[], size_t n,
            const fmi2Integer order[], fmi2Real v[]))
UNSUPPORTED(fmi2CancelStep, (fmi2Component c))
UNSUPPORTED(fmi2GetStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Status *v))
UNSUPPORTED(fmi2GetRealStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Real *v))
UNSUPPORTED(fmi2GetIntegerStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Integer *v))
UNSUPPORTED(fmi2GetBooleanStatus, (fmi2Component c, const fmi2StatusKind k, fmi2Boolean *v))
UNSUPPORTED(fmi2GetStringStatus, (fmi2Component c, const fmi2StatusKind k, fmi2String *v))

/* ---------------------------------------------------------------- co-simulation */
/* The inputs' first derivatives for the next communication step (canInterpolateInputs) */
FMI2_EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                                   size_t n, const fmi2Integer order[],
                                                   const fmi2Real v[]) {
    Instance *m = (Instance *)c;
    size_t i;
    if (!m->cosim) {
        logf_(m, ST_ERROR, "error", "fmi2SetRealInputDerivatives: the instance is not for "
              "co-simulation");
        return fmi2Error;
    }
    for (i = 0; i < n; i++) {
        if (vr[i] < CS_VR_U || vr[i] >= CS_VR_U + CS_NU) {
            logf_(m, ST_ERROR, "error", "fmi2SetRealInputDerivatives: value reference %u is "
                  "not an input", (unsigned)vr[i]);
            return fmi2Error;
        }
        if (order[i] != 1) {
            logf_(m, ST_ERROR, "error", "fmi2SetRealInputDerivatives: order %d for value "
                  "reference %u: this FMU takes first derivatives only "
                  "(canInterpolateInputs)", (int)order[i], (unsigned)vr[i]);
            return fmi2Error;
        }
        if (!isfinite(v[i])) {
            logf_(m, ST_ERROR, "error", "fmi2SetRealInputDerivatives: derivative %g of value "
                  "reference %u is not finite", v[i], (unsigned)vr[i]);
            return fmi2Error;
        }
        m->du[vr[i] - CS_VR_U] = v[i];
        m->has_du = 1;
    }
    return fmi2OK;
}

FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no_prior) {
    (void)no_prior;
    return (fmi2Status)rb_do_step((Instance *)c, t, h, "fmi2DoStep");
}

FMI2_EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference unk[],
                                                    size_t n_unk, const fmi2ValueReference kn[], size_t n_kn,
                                                    const fmi2Real seed[], fmi2Real sens[]) {
    return (fmi2Status)core_directional((Instance *)c, unk, n_unk, kn, n_kn, seed, sens,
                                        "fmi2GetDirectionalDerivative");
}

/* ---------------------------------------------------------------- model exchange */
FMI2_EXPORT fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    int values_changed, terminate, st;
    st = core_event((Instance *)c, &values_changed, &terminate);
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = terminate;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = values_changed;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return (fmi2Status)st;
}

