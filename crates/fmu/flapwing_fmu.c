/* flapwing's wing set as an FMI 2.0 co-simulation FMU.
 *
 * Inputs: the body's state (CoM position and velocity in the world, the world_from_body
 * quaternion, the angular velocity in the body frame) and flapsim's controls (offsets from
 * the model's nominal kinematics, SI). Outputs: the wings' force and moment about the CoM,
 * body frame, averaged over the last communication step. The FMU holds the wings' own state
 * (phase, actuated wing dynamics) through the C ABI (crates/ffi, libflapwing.a, linked in
 * statically); the host integrates the body.
 *
 * doStep(t, h): h must be a whole number n >= 1 of element steps dt (the calculated
 * parameter element_dt_s) to within STEP_TOLERANCE of one step; the FMU takes n element
 * steps, each from the body state held by the inputs (constant over h, as the master holds
 * them), and outputs the arithmetic mean of their wrenches: the impulse over h divided by h.
 * For n = 1 that is the element step's wrench bit for bit. Controls apply through
 * flapwing_wings_set_controls when an input changes: at the start of the next wingbeat
 * (immediately before the first step).
 *
 * Trim (the Boolean parameter `trim`): when the model loads, the wings are trimmed at the
 * flight condition (trim_forward_speed_m_s, trim_climb_rate_m_s) with
 * flapwing_wings_trim, which sets the trimmed controls and freezes the induced inflow at
 * the condition; the calculated parameters trim_* give the attitude, velocity and power at
 * trim (the body state to hold for a trimmed flight), and the control inputs become offsets
 * from the trimmed controls. A condition that does not trim fails initialization with the
 * C ABI's message.
 *
 * Errors: a bad model name or file (at the end of initialization), a NaN or infinite input
 * (C ABI FLAPWING_INVALID_ARGUMENT: fmi2Discard, the element not advanced), a communication
 * step that is no whole number of element steps, a diverged wing (fmi2Error): each logged
 * through the logger callback with the C ABI's own message; nothing aborts the process.
 *
 * The FMI 2.0 types and function declarations come from the standard headers (fmpy ships
 * them, fmpy/c-code; build.sh finds them). One instance is one wing set; instances are
 * independent (the C ABI keeps no shared state but each thread's last error message). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "flapwing.h"
#include "flapwing_fmu_vars.h"

/* A communication step may miss a whole number of element steps by this fraction of one
 * step: floating-point time grids (t = t0 + k h) are off by ~1e-16 t / dt steps, far below. */
#define STEP_TOLERANCE 1e-6

typedef enum { INSTANTIATED, INITIALIZATION, STEPPING, TERMINATED, FAILED } Phase;

typedef struct {
  fmi2CallbackLogger logger;
  fmi2ComponentEnvironment env;
  char *name;
  fmi2Boolean debug_logging;
  Phase phase;
  char *model;                      /* the String parameter */
  double real[FLAPWING_FMU_N_REALS]; /* every Real variable, by value reference */
  fmi2Integer element_steps;
  FlapwingWings *wings;             /* created at the end of initialization (or on demand) */
  FlapwingControls applied;         /* the controls last passed to the wing set */
  fmi2Boolean discarded;            /* the last doStep was discarded (a bad input) */
  fmi2Boolean trim;                 /* the Boolean parameter */
  FlapwingControls trimmed;         /* the controls trim found (zero without trim) */
  double start_time_s;
  size_t inflow_pairs;              /* the wings' pairs whose wake answers (at their build) */
} Fmu;

static const double real_start[FLAPWING_FMU_N_REALS] = {
#define START(name, vr, causality, variability, start, ...) [vr] = start,
    FLAPWING_FMU_REALS(START)
#undef START
};
static const char *const real_name[FLAPWING_FMU_N_REALS] = {
#define NAME(name, vr, ...) [vr] = #name,
    FLAPWING_FMU_REALS(NAME)
#undef NAME
};
static const char *const real_causality[FLAPWING_FMU_N_REALS] = {
#define CAUSALITY(name, vr, causality, ...) [vr] = causality,
    FLAPWING_FMU_REALS(CAUSALITY)
#undef CAUSALITY
};

/* Logs through the host's callback: errors and warnings always, debug only when enabled. */
static void log_msg(const Fmu *f, fmi2Status status, const char *category, const char *fmt, ...) {
  if (!f->logger || (status == fmi2OK && !f->debug_logging)) return;
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  /* The message is a printf format for the logger: pass ours as an argument. */
  f->logger(f->env, f->name, status, category, "%s", buf);
}

static fmi2Status fail(Fmu *f, fmi2Status status, const char *fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  log_msg(f, status, status == fmi2Warning ? "logStatusWarning" : "logStatusError", "%s", buf);
  if (status == fmi2Error || status == fmi2Fatal) f->phase = FAILED;
  return status;
}

static const char *status_name(FlapwingStatus s) {
  switch (s) {
    case FLAPWING_OK: return "ok";
    case FLAPWING_NULL_POINTER: return "null pointer";
    case FLAPWING_INVALID_ARGUMENT: return "invalid argument";
    case FLAPWING_MODEL_ERROR: return "model error";
    case FLAPWING_IO_ERROR: return "I/O error";
    case FLAPWING_DIVERGED: return "diverged";
    case FLAPWING_PANIC: return "panic (a bug in flapwing)";
  }
  return "unknown status";
}

static char *dup_string(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d) memcpy(d, s, n);
  return d;
}

/* Start values; the outputs are zero until the first doStep, the element step is NaN until
 * the model is loaded. */
static void reset_values(Fmu *f) {
  memcpy(f->real, real_start, sizeof f->real);
  for (int i = 0; i < 3; i++) f->real[VR_force_body_n_x + i] = f->real[VR_moment_body_nm_x + i] = 0.0;
  for (int i = 0; i < 6; i++) f->real[VR_inflow_pair0_mean_m_s + i] = 0.0;
  f->element_steps = 0;
  f->inflow_pairs = 0;
  f->discarded = fmi2False;
  memset(&f->applied, 0, sizeof f->applied);
  memset(&f->trimmed, 0, sizeof f->trimmed);
  flapwing_wings_free(f->wings);
  f->wings = NULL;
}

/* The wings' dynamic inflow states into the inflow outputs: pairs 0 and 1 (zero for a pair
 * the model does not have, or whose wake does not answer). */
static void inflow_outputs(Fmu *f) {
  for (size_t p = 0; p < 2; p++) {
    FlapwingInflow s = {0};
    if (p < f->inflow_pairs && f->wings) flapwing_wings_inflow(f->wings, p, &s);
    f->real[VR_inflow_pair0_mean_m_s + 3 * p] = s.mean_m_s;
    f->real[VR_inflow_pair0_fore_m_s + 3 * p] = s.fore_m_s;
    f->real[VR_inflow_pair0_left_m_s + 3 * p] = s.left_m_s;
  }
}

/* A path (contains '/' or ends in ".toml") is a model file; anything else a built-in name. */
static int is_path(const char *model) {
  size_t n = strlen(model);
  return strchr(model, '/') != NULL || (n >= 5 && strcmp(model + n - 5, ".toml") == 0);
}

/* Creates the wing set from the parameters if it does not exist yet. */
static fmi2Status ensure_wings(Fmu *f) {
  if (f->wings) return fmi2OK;
  double dt_s = f->real[VR_dt_s];
  if (!(dt_s >= 0.0) || isinf(dt_s))
    return fail(f, fmi2Error, "parameter dt_s = %g s: must be 0 (the model's own step) or a finite step > 0 of at most 1/10 of the wingbeat period", dt_s);
  FlapwingStatus s = is_path(f->model) ? flapwing_wings_from_file(f->model, dt_s, &f->wings)
                                       : flapwing_wings_from_builtin(f->model, dt_s, &f->wings);
  if (s != FLAPWING_OK)
    return fail(f, fmi2Error, "model \"%s\": %s: %s", f->model, status_name(s), flapwing_last_error());
  s = flapwing_wings_dt_s(f->wings, &f->real[VR_element_dt_s]);
  if (s != FLAPWING_OK) return fail(f, fmi2Error, "element step: %s: %s", status_name(s), flapwing_last_error());
  log_msg(f, fmi2OK, "logCalls", "model \"%s\": element step %.17g s", f->model, f->real[VR_element_dt_s]);
  if (f->trim) {
    double u = f->real[VR_trim_forward_speed_m_s], w = f->real[VR_trim_climb_rate_m_s];
    FlapwingTrim t;
    s = flapwing_wings_trim(f->wings, u, w, &t);
    if (s != FLAPWING_OK) {
      fmi2Status r = fail(f, fmi2Error, "trim at %g m/s forward, %g m/s climb: %s: %s", u, w,
                          status_name(s), flapwing_last_error());
      flapwing_wings_free(f->wings);
      f->wings = NULL;
      return r;
    }
    f->trimmed = t.controls;
    f->applied = t.controls; /* in force on the wings already */
    for (int i = 0; i < 4; i++) f->real[VR_trim_world_from_body_w + i] = t.world_from_body_wxyz[i];
    for (int i = 0; i < 3; i++) f->real[VR_trim_velocity_world_m_s_x + i] = t.velocity_world_m_s[i];
    f->real[VR_trim_aero_power_w] = t.aero_power_w;
    log_msg(f, fmi2OK, "logCalls", "trimmed at %g m/s forward, %g m/s climb: body pitch %.6g rad", u, w,
            t.pitch_rad);
  }
  f->inflow_pairs = 0;
  flapwing_wings_inflow_pairs(f->wings, &f->inflow_pairs);
  inflow_outputs(f);
  return fmi2OK;
}

/* The controls of the inputs: offsets from the model's nominal kinematics, or with trim from
 * the trimmed controls `base` (zero without trim). */
static FlapwingControls controls_from_inputs(const double *r, const FlapwingControls *base) {
  FlapwingControls c = {
      .mean_stroke_rad = base->mean_stroke_rad + r[VR_control_mean_stroke_rad],
      .amplitude_rad = base->amplitude_rad + r[VR_control_amplitude_rad],
      .pitch_bias_rad = base->pitch_bias_rad + r[VR_control_pitch_bias_rad],
      .aoa_rad = base->aoa_rad + r[VR_control_aoa_rad],
      .freq_hz = base->freq_hz + r[VR_control_freq_hz],
      .diff_amplitude_rad = base->diff_amplitude_rad + r[VR_control_diff_amplitude_rad],
      .diff_pitch_bias_rad = base->diff_pitch_bias_rad + r[VR_control_diff_pitch_bias_rad],
      .diff_mean_stroke_rad = base->diff_mean_stroke_rad + r[VR_control_diff_mean_stroke_rad],
      .bias_v = base->bias_v + r[VR_control_bias_v],
      .amplitude_v = base->amplitude_v + r[VR_control_amplitude_v],
      .diff_amplitude_v = base->diff_amplitude_v + r[VR_control_diff_amplitude_v],
      .diff_bias_v = base->diff_bias_v + r[VR_control_diff_bias_v],
      .diff_second_harmonic = base->diff_second_harmonic + r[VR_control_diff_second_harmonic],
  };
  return c;
}

static FlapwingBodyState body_from_inputs(const double *r) {
  FlapwingBodyState b = {
      .position_m = {r[VR_position_world_m_x], r[VR_position_world_m_y], r[VR_position_world_m_z]},
      .world_from_body_wxyz = {r[VR_world_from_body_w], r[VR_world_from_body_x],
                               r[VR_world_from_body_y], r[VR_world_from_body_z]},
      .velocity_world_m_s = {r[VR_velocity_world_m_s_x], r[VR_velocity_world_m_s_y],
                             r[VR_velocity_world_m_s_z]},
      .angular_velocity_body_rad_s = {r[VR_angular_velocity_body_rad_s_x],
                                      r[VR_angular_velocity_body_rad_s_y],
                                      r[VR_angular_velocity_body_rad_s_z]},
  };
  return b;
}

/* ---------------------------------------------------------------- common functions */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
  (void)nCategories;
  (void)categories; /* errors and warnings are always logged; the switch is for logCalls */
  if (!c) return fmi2Error;
  ((Fmu *)c)->debug_logging = loggingOn;
  return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
  (void)fmuResourceLocation;
  (void)visible;
  Fmu probe = {.logger = functions ? functions->logger : NULL,
               .env = functions ? functions->componentEnvironment : NULL,
               .name = (char *)(instanceName ? instanceName : "flapwing_wings")};
  char guid[40];
  flapwing_fmu_guid(guid);
  if (fmuType != fmi2CoSimulation) {
    fail(&probe, fmi2Error, "fmi2Instantiate: this FMU is co-simulation only");
    return NULL;
  }
  if (!fmuGUID || strcmp(fmuGUID, guid) != 0) {
    fail(&probe, fmi2Error, "fmi2Instantiate: GUID %s does not match the binary's %s (a modelDescription.xml from another build)",
         fmuGUID ? fmuGUID : "(null)", guid);
    return NULL;
  }
  Fmu *f = calloc(1, sizeof *f);
  if (!f) return NULL;
  *f = probe;
  f->name = dup_string(probe.name);
  f->model = dup_string(FLAPWING_FMU_DEFAULT_MODEL);
  if (!f->name || !f->model) {
    free(f->name);
    free(f->model);
    free(f);
    return NULL;
  }
  f->debug_logging = loggingOn;
  f->phase = INSTANTIATED;
  reset_values(f);
  log_msg(f, fmi2OK, "logCalls", "fmi2Instantiate: flapwing %s", flapwing_version());
  return f;
}

void fmi2FreeInstance(fmi2Component c) {
  Fmu *f = c;
  if (!f) return;
  flapwing_wings_free(f->wings);
  free(f->model);
  free(f->name);
  free(f);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  (void)toleranceDefined, (void)tolerance, (void)stopTimeDefined, (void)stopTime;
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (f->phase != INSTANTIATED) return fail(f, fmi2Error, "fmi2SetupExperiment: only before initialization");
  f->start_time_s = startTime;
  return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (f->phase != INSTANTIATED) return fail(f, fmi2Error, "fmi2EnterInitializationMode: only once, after fmi2Instantiate or fmi2Reset");
  f->phase = INITIALIZATION;
  return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (f->phase != INITIALIZATION) return fail(f, fmi2Error, "fmi2ExitInitializationMode: not in initialization mode");
  fmi2Status s = ensure_wings(f);
  if (s != fmi2OK) return s;
  f->phase = STEPPING;
  return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  f->phase = TERMINATED;
  return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  char *model = dup_string(FLAPWING_FMU_DEFAULT_MODEL);
  if (!model) return fail(f, fmi2Error, "fmi2Reset: out of memory");
  free(f->model);
  f->model = model;
  f->trim = fmi2False;
  reset_values(f);
  f->start_time_s = 0.0;
  f->phase = INSTANTIATED;
  return fmi2OK;
}

/* ---------------------------------------------------------------- getters and setters */

static fmi2Status check_vrs(Fmu *f, const char *fn, const fmi2ValueReference vr[], size_t nvr, size_t count) {
  if (nvr > 0 && !vr) return fail(f, fmi2Error, "%s: value references NULL", fn);
  for (size_t i = 0; i < nvr; i++)
    if (vr[i] >= count) return fail(f, fmi2Error, "%s: no such value reference %u", fn, vr[i]);
  return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2GetReal", vr, nvr, FLAPWING_FMU_N_REALS) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) {
    /* The element step and the trim are known once the model is: create the wing set on
     * demand in initialization mode (a master reads calculated parameters there). */
    if (real_causality[vr[i]][0] == 'c' && !f->wings && f->phase == INITIALIZATION &&
        ensure_wings(f) != fmi2OK)
      return fmi2Error;
    value[i] = f->real[vr[i]];
  }
  return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2SetReal", vr, nvr, FLAPWING_FMU_N_REALS) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) {
    const char *causality = real_causality[vr[i]];
    if (strcmp(causality, "input") == 0) {
      f->real[vr[i]] = value[i]; /* NaN is the C ABI's to report, at the next step */
    } else if (strcmp(causality, "parameter") == 0) {
      if (f->phase != INSTANTIATED && f->phase != INITIALIZATION)
        return fail(f, fmi2Error, "fmi2SetReal: %s is a fixed parameter: set it before initialization ends", real_name[vr[i]]);
      f->real[vr[i]] = value[i];
      flapwing_wings_free(f->wings); /* rebuilt with the new value */
      f->wings = NULL;
    } else {
      return fail(f, fmi2Error, "fmi2SetReal: %s is a %s: it cannot be set", real_name[vr[i]], causality);
    }
  }
  return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2GetInteger", vr, nvr, 1) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) value[i] = f->element_steps;
  return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
  (void)value;
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (nvr == 0) return fmi2OK;
  return fail(f, fmi2Error, "fmi2SetInteger: element_steps (value reference %u) is an output", vr ? vr[0] : 0);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2GetBoolean", vr, nvr, 1) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) value[i] = f->trim;
  return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2SetBoolean", vr, nvr, 1) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) {
    if (f->phase != INSTANTIATED && f->phase != INITIALIZATION)
      return fail(f, fmi2Error, "fmi2SetBoolean: trim is a fixed parameter: set it before initialization ends");
    f->trim = value[i] ? fmi2True : fmi2False;
    flapwing_wings_free(f->wings); /* rebuilt (and trimmed) with the new value */
    f->wings = NULL;
  }
  return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2GetString", vr, nvr, 1) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) value[i] = f->model;
  return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (check_vrs(f, "fmi2SetString", vr, nvr, 1) != fmi2OK) return fmi2Error;
  for (size_t i = 0; i < nvr; i++) {
    if (f->phase != INSTANTIATED && f->phase != INITIALIZATION)
      return fail(f, fmi2Error, "fmi2SetString: model is a fixed parameter: set it before initialization ends");
    if (!value[i]) return fail(f, fmi2Error, "fmi2SetString: model: NULL string");
    char *model = dup_string(value[i]);
    if (!model) return fail(f, fmi2Error, "fmi2SetString: out of memory");
    free(f->model);
    f->model = model;
    flapwing_wings_free(f->wings);
    f->wings = NULL;
  }
  return fmi2OK;
}

/* ---------------------------------------------------------------- co-simulation */

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
  (void)noSetFMUStatePriorToCurrentPoint;
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (f->phase != STEPPING) return fail(f, fmi2Error, "fmi2DoStep: not initialized (or terminated, or failed)");
  f->discarded = fmi2False;
  const double dt_s = f->real[VR_element_dt_s];
  const double h = communicationStepSize;
  /* Whole element steps covering h. */
  const double steps_real = h / dt_s;
  const double n_real = round(steps_real);
  if (!(h > 0.0) || !(n_real >= 1.0) || fabs(steps_real - n_real) > STEP_TOLERANCE || n_real > 1e9)
    return fail(f, fmi2Error,
                "fmi2DoStep: communication step %.17g s is not a whole number of element steps of %.17g s "
                "(h/dt = %.9f); use a multiple of element_dt_s",
                h, dt_s, steps_real);
  /* The master's clock and the element's must agree (the FMU cannot go back). */
  const double done = (currentCommunicationPoint - f->start_time_s) / dt_s;
  if (fabs(done - (double)f->element_steps) > STEP_TOLERANCE)
    return fail(f, fmi2Error,
                "fmi2DoStep: communication point %.17g s, but the wings are at %.17g s (%d element steps of %.17g s)",
                currentCommunicationPoint, f->start_time_s + f->element_steps * dt_s, (int)f->element_steps, dt_s);

  FlapwingControls controls = controls_from_inputs(f->real, &f->trimmed);
  if (memcmp(&controls, &f->applied, sizeof controls) != 0) {
    FlapwingStatus s = flapwing_wings_set_controls(f->wings, &controls);
    f->discarded = s == FLAPWING_INVALID_ARGUMENT;
    if (s != FLAPWING_OK)
      return fail(f, s == FLAPWING_INVALID_ARGUMENT ? fmi2Discard : fmi2Error, "controls at t = %.17g s: %s: %s",
                  currentCommunicationPoint, status_name(s), flapwing_last_error());
    f->applied = controls;
  }

  const FlapwingBodyState body = body_from_inputs(f->real);
  const long n = (long)n_real;
  FlapwingWrench sum;
  memset(&sum, 0, sizeof sum);
  for (long k = 0; k < n; k++) {
    FlapwingWrench w;
    FlapwingStatus s = flapwing_wings_step(f->wings, &body, &w);
    if (s != FLAPWING_OK) {
      f->discarded = s == FLAPWING_INVALID_ARGUMENT;
      /* A bad input (NaN, a zero quaternion) leaves the element where it was: discard the
       * step; anything else (divergence, a bug) ends the simulation. */
      return fail(f, s == FLAPWING_INVALID_ARGUMENT ? fmi2Discard : fmi2Error,
                  "element step %ld of %ld at t = %.17g s: %s: %s", k + 1, n,
                  f->start_time_s + f->element_steps * dt_s, status_name(s), flapwing_last_error());
    }
    f->element_steps++;
    for (int i = 0; i < 3; i++) {
      /* The first step's wrench is taken as is (0.0 + -0.0 would lose the sign of zero). */
      sum.force_body_n[i] = k == 0 ? w.force_body_n[i] : sum.force_body_n[i] + w.force_body_n[i];
      sum.moment_body_nm[i] = k == 0 ? w.moment_body_nm[i] : sum.moment_body_nm[i] + w.moment_body_nm[i];
    }
  }
  for (int i = 0; i < 3; i++) {
    f->real[VR_force_body_n_x + i] = sum.force_body_n[i] / (double)n;
    f->real[VR_moment_body_nm_x + i] = sum.moment_body_nm[i] / (double)n;
  }
  inflow_outputs(f);
  return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
  return c ? fail(c, fmi2Error, "fmi2CancelStep: steps are synchronous") : fmi2Error;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
  (void)s, (void)value;
  return c ? fail(c, fmi2Discard, "fmi2GetStatus: steps are synchronous; no status to ask for") : fmi2Error;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (s != fmi2LastSuccessfulTime || !value) return fail(f, fmi2Discard, "fmi2GetRealStatus: only fmi2LastSuccessfulTime");
  *value = f->start_time_s + f->element_steps * f->real[VR_element_dt_s];
  return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
  (void)s, (void)value;
  return c ? fail(c, fmi2Discard, "fmi2GetIntegerStatus: no integer status") : fmi2Error;
}

/* fmi2Terminated, asked after a discarded step: the FMU cannot go on from a bad input (a
 * NaN body state), so it asks the master to end the simulation at the last good time. */
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (s != fmi2Terminated || !value) return fail(f, fmi2Discard, "fmi2GetBooleanStatus: only fmi2Terminated");
  *value = f->discarded;
  return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
  (void)s, (void)value;
  return c ? fail(c, fmi2Discard, "fmi2GetStringStatus: steps are synchronous") : fmi2Error;
}

/* ---------------------------------------------------------------- FMU state
 * fmi2GetFMUstate / fmi2SetFMUstate / fmi2FreeFMUstate (canGetAndSetFMUstate): a master that
 * steps back (a variable-step master rejecting a step, a finite-difference linearisation, an
 * optimiser's rollouts) gets the FMU back as it was, wings included: the steps that follow
 * repeat bit for bit. A state holds the instance's values and a copy of its wings; getting
 * into an existing state saves the wings into its copy (flapwing_wings_save: no table of
 * kinematic loads, no allocation), setting one restores them (flapwing_wings_restore); wings
 * rebuilt since (a new parameter value, fmi2Reset) are replaced by a copy of the state's. */

typedef struct {
  Fmu values;            /* the instance's fields; its `wings`, `model`, `name` unused */
  char *model;
  FlapwingWings *wings;  /* NULL if the instance had none */
} FmuState;

/* `*to` becomes a copy of `from` (NULL: none): saved into when both exist and are copies of
 * one build, else cloned. 0 on success. */
static int copy_wings(FlapwingWings **to, const FlapwingWings *from, int restore) {
  if (!from) {
    flapwing_wings_free(*to);
    *to = NULL;
    return 0;
  }
  if (*to) {
    FlapwingStatus s = restore ? flapwing_wings_restore(*to, from) : flapwing_wings_save(from, *to);
    if (s == FLAPWING_OK) return 0;
  }
  FlapwingWings *w = NULL;
  if (flapwing_wings_clone(from, &w) != FLAPWING_OK) return -1;
  flapwing_wings_free(*to);
  *to = w;
  return 0;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  if (!s) return fail(f, fmi2Error, "fmi2GetFMUstate: the state pointer is NULL");
  FmuState *st = *s;
  if (!st) {
    st = calloc(1, sizeof *st);
    if (!st) return fail(f, fmi2Error, "fmi2GetFMUstate: out of memory");
  }
  char *model = dup_string(f->model);
  if (!model || copy_wings(&st->wings, f->wings, 0) != 0) {
    free(model);
    if (!*s) {
      flapwing_wings_free(st->wings);
      free(st);
    }
    return fail(f, fmi2Error, "fmi2GetFMUstate: copying the wings: %s",
                model ? flapwing_last_error() : "out of memory");
  }
  free(st->model);
  st->model = model;
  st->values = *f;
  *s = st;
  return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
  Fmu *f = c;
  if (!f) return fmi2Error;
  const FmuState *st = s;
  if (!st) return fail(f, fmi2Error, "fmi2SetFMUstate: the state is NULL; allowed: one from fmi2GetFMUstate");
  char *model = dup_string(st->model);
  if (!model || copy_wings(&f->wings, st->wings, 1) != 0) {
    free(model);
    return fail(f, fmi2Error, "fmi2SetFMUstate: copying the wings: %s",
                model ? flapwing_last_error() : "out of memory");
  }
  /* Everything but what the instance owns (its name, callbacks, wings and model string). */
  FlapwingWings *wings = f->wings;
  char *name = f->name;
  fmi2CallbackLogger logger = f->logger;
  fmi2ComponentEnvironment env = f->env;
  fmi2Boolean debug = f->debug_logging;
  free(f->model);
  *f = st->values;
  f->wings = wings;
  f->model = model;
  f->name = name;
  f->logger = logger;
  f->env = env;
  f->debug_logging = debug;
  return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) {
  if (!s || !*s) return fmi2OK;
  FmuState *st = *s;
  flapwing_wings_free(st->wings);
  free(st->model);
  free(st);
  *s = NULL;
  (void)c;
  return fmi2OK;
}

/* ---------------------------------------------------------------- not supported
 * (the model description says so: no serialized FMU state, no directional derivatives, no
 * input interpolation, maxOutputDerivativeOrder 0) */

static fmi2Status unsupported(fmi2Component c, const char *fn) {
  return c ? fail(c, fmi2Error, "%s: not supported by this FMU (see its modelDescription.xml)", fn) : fmi2Error;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n) {
  (void)s, (void)n;
  return unsupported(c, "fmi2SerializedFMUstateSize");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
  (void)s, (void)b, (void)n;
  return unsupported(c, "fmi2SerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s) {
  (void)b, (void)n, (void)s;
  return unsupported(c, "fmi2DeSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz, const fmi2Real dv[], fmi2Real dz[]) {
  (void)u, (void)nu, (void)z, (void)nz, (void)dv, (void)dz;
  return unsupported(c, "fmi2GetDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
  (void)vr, (void)nvr, (void)order, (void)value;
  return unsupported(c, "fmi2SetRealInputDerivatives");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
  (void)vr, (void)nvr, (void)order, (void)value;
  return unsupported(c, "fmi2GetRealOutputDerivatives");
}
