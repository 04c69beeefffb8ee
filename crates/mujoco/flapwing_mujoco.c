/* flapwing_mujoco.c: flapwing's wing set as a MuJoCo engine plugin, `flapwing.wings`.
 *
 * A passive-force plugin attached to one body (`<body><plugin instance="..."/></body>`). At
 * every mj_step it hands the body's state at t_k to a flapwing wing set (the C ABI of
 * crates/ffi, linked statically) and applies the wrench the wings return for [t_k, t_k + dt]
 * to the body, at its centre of mass, through qfrc_passive (mj_applyFT).
 *
 * Frames and units (SI): flapwing's body frame is the MuJoCo body's frame (xquat) moved to
 * the body's centre of mass (xipos): x forward, y left, z up; world z up (MuJoCo's default
 * gravity axis). The model's body mass and inertia are the MJCF's business (see
 * examples/mujoco/fly.xml); the plugin reads neither.
 *
 * Stepping: the wings advance once per mj_step, at the first passive-force evaluation of the
 * step (the state at t_k); later evaluations within the same step (RK4's stages, a user's
 * mj_forward) apply the same wrench, held over the step as flapwing's own host does; the
 * `advance` callback (after MuJoCo's time integration) marks the next evaluation as a new
 * step. mj_resetData restarts the wings from t = 0 (a copy of the wings made at init, so a
 * reset costs a copy, not a new build and trim); mj_copyData gives the copy the source's wings
 * as they are (flapwing_wings_clone), so both fly on alike.
 *
 * Errors through MuJoCo's own channels: a bad attribute or model (or `<option timestep>` not
 * > 0, or longer than the wing set allows: 1/10 of the wingbeat) makes `init` fail with a
 * mju_error naming what is wrong, after freeing what it allocated: the error MuJoCo raises
 * for any failed plugin init anyway ("plugin->init failed"), here with the reason, once (a
 * mju_warning before a plain failure appears twice in the compiler's message). The compiler
 * reports it as the load error and the Python bindings raise it. At run time every failure is counted in d->warning as MuJoCo counts its
 * own (number, lastinfo): a body state the wings refuse (non-finite, or a speed whose loads
 * overflow) is mjWARN_BADQPOS (position or attitude) or mjWARN_BADQVEL (velocities), info the
 * body's first DOF; a failed or diverged step or a non-finite wrench mjWARN_BADQACC, same info;
 * actuator controls the wings refuse mjWARN_BADCTRL, info the actuator. The message saying
 * what and why goes out once per run of failures (mju_warning). The wrench is then zero.
 * Nothing at run time calls mju_error.
 *
 * Controls: the model's `[controls]` (or, with the `trim` attribute "U W", the trim at forward
 * speed U and climb rate W, m/s: flapwing_wings_trim), with the control attributes in place
 * of theirs, set at load. At run time, actuators named `<plugin instance name>:<field>` (the field's SI name,
 * e.g. `wings:diff_amplitude_rad`; give them zero gear so that they push nothing themselves)
 * drive those fields: their ctrl values (SI) go to the wings when they change and take effect
 * at the next wingbeat, as in flapwing's own hosts.
 *
 * Plugin state (m->plugin_statenum = 7 + 3 per wing pair whose wake answers): the wrench
 * applied in the last step, body frame: force_body_n[3], moment_body_nm[3] (zero before the
 * first step and after a failure); the wing step the state is at (the steps taken before the
 * current mj_step; set at each advance), so that MuJoCo's state functions carry the wings'
 * place in time; then, for a model with `[aero] inflow = "dynamic"` (none with `trim`, which
 * freezes the inflow), each pair's dynamic inflow states the step starts from (mean_m_s,
 * fore_m_s, left_m_s: FlapwingInflow), set at each advance: states of the system, which a
 * host that changes them (mj_setState) hands to the wings at the next step. A state set back by the
 * host (mj_setState; mjd_transitionFD, which steps from a state, sets it back and steps again
 * from a perturbed one) finds the wings a step ahead: with the attribute rewind="true" the
 * plugin saves the wings before every step (flapwing_wings_save, about 0.05 us for the fly)
 * and puts them back (flapwing_wings_restore), so a perturbed step is the same wing step as
 * the nominal one and the derivatives are those of the flight; without it, or further back
 * than one step, the wings go on from where they are and the plugin warns once.
 */

#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

#include "flapwing.h"

#define PLUGIN_NAME "flapwing.wings"
#define NSTATE 7 /* without the inflow states: 3 per pair after these */
#define MESSAGE_CHARS 1024

#include "config.h"

/* One plugin instance in one mjData. */
typedef struct Instance {
  Config config;
  int body_id;                  /* the body the plugin is attached to */
  int free_dof;                 /* its free joint's first DOF if it hangs from the world by
                                 * one free joint (read qvel, write qfrc_passive directly), else
                                 * -1 (mj_objectVelocity, mj_applyFT) */
  FlapwingWings *wings;         /* NULL if a rebuild on reset failed (warned) */
  FlapwingWings *pristine;      /* the wings as built (and trimmed) at init, never stepped:
                                 * cloned at each reset instead of building (and trimming)
                                 * them again, which costs up to seconds (the hummingbird's
                                 * trim); NULL: rebuild */
  FlapwingWings *saved;         /* with the `rewind` attribute: the wings as they were before
                                 * the last step (flapwing_wings_save), to go back to when the
                                 * host sets the state back a step; else NULL */
  uint64_t saved_steps;         /* the wing steps taken when `saved` was saved */
  FlapwingControls saved_sent;  /* `sent` then */
  int stepped;                  /* the wings have stepped for the current mj_step */
  uint64_t steps;               /* wing steps since creation */
  int failing;                  /* the last step failed (warned once per run of failures) */
  FlapwingWrench wrench;        /* applied in the current step, body frame */
  double inertia_body[9];       /* free joint: the body's inertia about its centre of mass,
                                 * body frame (row-major), for the gyroscopic correction */
  /* Controls driven by actuators named `<instance name>:<field>` (ctrl in SI). */
  int nactuated;
  int actuator_id[NCONTROL];
  int actuator_control[NCONTROL]; /* index into kControls */
  FlapwingControls base;        /* the model's controls with the attributes applied */
  FlapwingControls sent;        /* the controls last handed to the wings */
  int control_failing;          /* the last actuator controls were refused (warned once) */
  int time_warned;              /* the plugin state was set to another step (warned once) */
  size_t inflow_pairs;          /* the wing pairs whose inflow states the plugin state holds
                                 * (3 each after the first NSTATE: the wings' dynamic inflow) */
  int inflow_failing;           /* inflow states from the plugin state were refused (warned) */
} Instance;

/*---------------------------------- the wing set ------------------------------------------*/

/* Whether the model names a built-in (letters, digits and '_' only) rather than a file. */
static int is_builtin_name(const char *s) {
  for (; *s; s++) {
    char ch = *s;
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
          ch == '_')) {
      return 0;
    }
  }
  return 1;
}

/* A wing set from the config, with its controls (the model's, with the control attributes
 * in place of theirs: written to *base) and wind; on failure NULL and a message. */
static FlapwingWings *create_wings(const Config *c, FlapwingControls *base, char *msg,
                                   size_t nmsg) {
  FlapwingWings *w = NULL;
  FlapwingStatus st = is_builtin_name(c->model)
                          ? flapwing_wings_from_builtin(c->model, c->dt_s, &w)
                          : flapwing_wings_from_file(c->model, c->dt_s, &w);
  if (st != FLAPWING_OK) {
    snprintf(msg, nmsg, "model `%s` (as %s, step %.17g s): %s", c->model,
             is_builtin_name(c->model) ? "a built-in name" : "a TOML file", c->dt_s,
             flapwing_last_error());
    return NULL;
  }
  /* Trim first (flapwing_wings_trim sets the trimmed controls and freezes the induced inflow
   * at the condition); the control attributes then replace their fields. */
  if (c->has_trim && flapwing_wings_trim(w, c->trim_m_s[0], c->trim_m_s[1], NULL) != FLAPWING_OK) {
    snprintf(msg, nmsg, "attribute `trim` (%.17g %.17g m/s): %s", c->trim_m_s[0], c->trim_m_s[1],
             flapwing_last_error());
    flapwing_wings_free(w);
    return NULL;
  }
  int any = 0;
  if (flapwing_wings_controls(w, base) != FLAPWING_OK) {
    snprintf(msg, nmsg, "reading the model's controls: %s", flapwing_last_error());
    flapwing_wings_free(w);
    return NULL;
  }
  for (int i = 0; i < NCONTROL; i++) {
    if (!c->has_control[i]) continue;
    size_t off = kControls[i].offset;
    *(double *)((char *)base + off) = *(const double *)((const char *)&c->controls + off);
    any = 1;
  }
  if (any && flapwing_wings_set_controls(w, base) != FLAPWING_OK) {
    snprintf(msg, nmsg, "control attributes: %s", flapwing_last_error());
    flapwing_wings_free(w);
    return NULL;
  }
  if (c->has_wind && flapwing_wings_set_wind(w, c->wind_world_m_s) != FLAPWING_OK) {
    snprintf(msg, nmsg, "attribute `wind`: %s", flapwing_last_error());
    flapwing_wings_free(w);
    return NULL;
  }
  return w;
}

/* The instance's wings (create_wings), told, on a body with a free joint, that MuJoCo's Euler
 * takes the body's gyroscopic term (its bias force) at the step's start: each step's moment
 * then carries the correction that makes the rates' update the midpoint rule of Euler's
 * equations, second order as the loads are (crates/mujoco/README.md, "Stepping"). */
static FlapwingWings *instance_wings(Instance *in, char *msg, size_t nmsg) {
  FlapwingWings *w = create_wings(&in->config, &in->base, msg, nmsg);
  if (w && in->free_dof >= 0 &&
      flapwing_wings_set_gyroscopic_host(w, in->inertia_body) != FLAPWING_OK) {
    snprintf(msg, nmsg, "the body's inertia: %s", flapwing_last_error());
    flapwing_wings_free(w);
    return NULL;
  }
  return w;
}

/*---------------------------------- the body ---------------------------------------------*/

/* A body on one free joint (the fly of fly.xml): its state and wrench straight from and into
 * the joint's DOFs, the cheapest way MuJoCo allows. qvel holds the velocity of the joint's
 * anchor (world) and the angular velocity in the body frame; the generalised force of a
 * wrench (F, M about the centre of mass) is F (world) and M + r x F about the anchor, body
 * frame, r from the anchor to the centre of mass: what mj_applyFT computes through the
 * body's Jacobian, without it. */
static void free_body_state(const mjModel *m, const mjData *d, int b, int dof,
                            FlapwingBodyState *s) {
  const mjtNum *R = d->xmat + 9 * b; /* body -> world */
  const mjtNum *w = d->qvel + dof + 3;
  mjtNum r[3], w_world[3], wxr[3];
  mju_sub3(r, d->xipos + 3 * b, d->xanchor + 3 * m->body_jntadr[b]);
  mju_mulMatVec3(w_world, R, w);
  mju_cross(wxr, w_world, r);
  for (int i = 0; i < 3; i++) {
    s->position_m[i] = d->xipos[3 * b + i];
    s->velocity_world_m_s[i] = d->qvel[dof + i] + wxr[i];
    s->angular_velocity_body_rad_s[i] = w[i];
  }
  for (int i = 0; i < 4; i++) s->world_from_body_wxyz[i] = d->xquat[4 * b + i];
}

static void free_body_apply(const mjModel *m, mjData *d, int b, int dof, const FlapwingWrench *w) {
  const mjtNum *R = d->xmat + 9 * b;
  mjtNum f_world[3], r[3], r_body[3], rxf[3];
  mju_mulMatVec3(f_world, R, w->force_body_n);
  mju_sub3(r, d->xipos + 3 * b, d->xanchor + 3 * m->body_jntadr[b]);
  mju_mulMatTVec3(r_body, R, r);
  mju_cross(rxf, r_body, w->force_body_n);
  for (int i = 0; i < 3; i++) {
    d->qfrc_passive[dof + i] += f_world[i];
    d->qfrc_passive[dof + 3 + i] += w->moment_body_nm[i] + rxf[i];
  }
}

/* The body's state for flapwing: position and velocity of the centre of mass (world),
 * attitude world_from_body (the body frame's xquat), angular velocity in the body frame. */
static void body_state(const mjModel *m, const mjData *d, int b, FlapwingBodyState *s) {
  mjtNum vel[6]; /* [angular; linear] at the centre of mass, world frame */
  mj_objectVelocity(m, d, mjOBJ_BODY, b, vel, 0);
  const mjtNum *q = d->xquat + 4 * b;
  mjtNum body_from_world[4];
  mju_negQuat(body_from_world, q);
  mjtNum w_body[3];
  mju_rotVecQuat(w_body, vel, body_from_world);
  for (int i = 0; i < 3; i++) {
    s->position_m[i] = d->xipos[3 * b + i];
    s->velocity_world_m_s[i] = vel[3 + i];
    s->angular_velocity_body_rad_s[i] = w_body[i];
  }
  for (int i = 0; i < 4; i++) s->world_from_body_wxyz[i] = q[i];
}

/* Counts a run-time warning in d->warning as MuJoCo's mj_warning does (without its generic
 * text: the caller's mju_warning says what happened). */
static void count_warning(mjData *d, int warning, int info) {
  d->warning[warning].lastinfo = info;
  d->warning[warning].number++;
}

static int all_finite(const double *x, int n) {
  for (int i = 0; i < n; i++) {
    if (!isfinite(x[i])) return 0;
  }
  return 1;
}

static int wrench_finite(const FlapwingWrench *w) {
  for (int i = 0; i < 3; i++) {
    if (!isfinite(w->force_body_n[i]) || !isfinite(w->moment_body_nm[i])) return 0;
  }
  return 1;
}

/* The controls from the instance's actuators (`<instance>:<field>`, ctrl in SI) on top of
 * the base controls, handed to the wings when they change (they take effect at the next
 * wingbeat); controls the model refuses are warned about once and the previous ones stay. */
static void actuator_controls(const mjModel *m, mjData *d, int instance, Instance *in) {
  FlapwingControls c = in->base;
  for (int k = 0; k < in->nactuated; k++) {
    size_t off = kControls[in->actuator_control[k]].offset;
    *(double *)((char *)&c + off) = d->ctrl[in->actuator_id[k]];
  }
  if (memcmp(&c, &in->sent, sizeof(c)) == 0) return;
  if (flapwing_wings_set_controls(in->wings, &c) != FLAPWING_OK) {
    int changed = in->actuator_id[0]; /* info: the first actuator whose control changed */
    for (int k = in->nactuated - 1; k >= 0; k--) {
      size_t off = kControls[in->actuator_control[k]].offset;
      if (memcmp((char *)&c + off, (char *)&in->sent + off, sizeof(double)) != 0) {
        changed = in->actuator_id[k];
      }
    }
    count_warning(d, mjWARN_BADCTRL, changed);
    if (!in->control_failing) {
      mju_warning("%s (instance %d, body `%s`, t = %.9g s): actuator controls refused: %s; the "
                  "previous controls stay in force",
                  PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, in->body_id), d->time,
                  flapwing_last_error());
    }
    in->control_failing = 1;
    return;
  }
  in->control_failing = 0;
  in->sent = c;
}

/* Maps the actuators named `<instance name>:<field>` to control fields; -1 and a message
 * for a name with an unknown field. */
static int map_actuators(const mjModel *m, int instance, Instance *in, char *msg, size_t nmsg) {
  const char *iname = mj_id2name(m, mjOBJ_PLUGIN, instance);
  in->nactuated = 0;
  if (!iname || !iname[0]) return 0;
  size_t n = strlen(iname);
  for (int a = 0; a < m->nu; a++) {
    const char *name = mj_id2name(m, mjOBJ_ACTUATOR, a);
    if (!name || strncmp(name, iname, n) != 0 || name[n] != ':') continue;
    const char *field = name + n + 1;
    int found = -1;
    for (int i = 0; i < NCONTROL; i++) {
      if (strcmp(field, kControls[i].si) == 0) found = i;
    }
    if (found < 0) {
      int len = snprintf(msg, nmsg, "actuator `%s` names no control field `%s`; allowed:", name,
                         field);
      for (int i = 0; i < NCONTROL && len > 0 && (size_t)len < nmsg; i++) {
        len += snprintf(msg + len, nmsg - (size_t)len, " %s:%s", iname, kControls[i].si);
      }
      return -1;
    }
    for (int k = 0; k < in->nactuated; k++) {
      if (in->actuator_control[k] == found) {
        snprintf(msg, nmsg, "actuators `%s` and `%s` both drive `%s`; allowed: one each",
                 mj_id2name(m, mjOBJ_ACTUATOR, in->actuator_id[k]), name, kControls[found].si);
        return -1;
      }
    }
    in->actuator_id[in->nactuated] = a;
    in->actuator_control[in->nactuated] = found;
    in->nactuated++;
  }
  return 0;
}

/* Steps the wings from the body's state at t_k; on any failure warns (once per run of
 * failures) and leaves a zero wrench. */
static void step_wings(const mjModel *m, mjData *d, int instance, Instance *in) {
  memset(&in->wrench, 0, sizeof(in->wrench));
  if (!in->wings) return; /* the rebuild on reset failed and was warned */
  if (in->nactuated > 0) actuator_controls(m, d, instance, in);
  FlapwingBodyState s;
  if (in->free_dof >= 0) {
    free_body_state(m, d, in->body_id, in->free_dof, &s);
  } else {
    body_state(m, d, in->body_id, &s);
  }
  FlapwingWrench w;
  FlapwingStatus st = flapwing_wings_step(in->wings, &s, &w);
  in->steps++;
  const char *why = NULL;
  int info = m->body_dofadr[in->body_id];
  if (st != FLAPWING_OK) {
    why = flapwing_last_error();
    int pose_ok = all_finite(s.position_m, 3) && all_finite(s.world_from_body_wxyz, 4);
    count_warning(d,
                  st != FLAPWING_INVALID_ARGUMENT ? mjWARN_BADQACC
                  : pose_ok                       ? mjWARN_BADQVEL
                                                  : mjWARN_BADQPOS,
                  info);
  } else if (!wrench_finite(&w)) {
    why = "the wings' wrench is not finite";
    count_warning(d, mjWARN_BADQACC, info);
  }
  if (why) {
    if (!in->failing) {
      mju_warning("%s (instance %d, body `%s`, t = %.9g s): %s; the wings apply no force while "
                  "this lasts",
                  PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, in->body_id), d->time, why);
    }
    in->failing = 1;
    return;
  }
  in->failing = 0;
  in->wrench = w;
}

/*---------------------------------- callbacks --------------------------------------------*/

/* The wing pairs whose wake answers (`[aero] inflow = "dynamic"`) in the instance's model,
 * from a build of its wings at the model's own step (the plugin state must be sized before
 * init builds them); 0 with the `trim` attribute (the trim freezes the inflow) or a model that
 * does not build (init then fails with the reason). */
static size_t inflow_pairs_of(const mjModel *m, int instance) {
  const char *model = mj_getPluginConfig(m, instance, "model");
  const char *trim = mj_getPluginConfig(m, instance, "trim");
  if (!model || !model[0] || (trim && trim[0])) return 0;
  FlapwingWings *w = NULL;
  FlapwingStatus st = is_builtin_name(model) ? flapwing_wings_from_builtin(model, 0.0, &w)
                                             : flapwing_wings_from_file(model, 0.0, &w);
  size_t n = 0;
  if (st != FLAPWING_OK || flapwing_wings_inflow_pairs(w, &n) != FLAPWING_OK) n = 0;
  flapwing_wings_free(w);
  return n;
}

static int plugin_nstate(const mjModel *m, int instance) {
  return NSTATE + 3 * (int)inflow_pairs_of(m, instance);
}

/* The wings' dynamic inflow states into the plugin state (after the first NSTATE). */
static void write_inflow(const Instance *in, mjtNum *state) {
  for (size_t p = 0; p < in->inflow_pairs; p++) {
    FlapwingInflow f = {0};
    if (in->wings) flapwing_wings_inflow(in->wings, p, &f);
    state[NSTATE + 3 * p] = f.mean_m_s;
    state[NSTATE + 3 * p + 1] = f.fore_m_s;
    state[NSTATE + 3 * p + 2] = f.left_m_s;
  }
}

/* Inflow states the host put into the plugin state (mj_setState; a perturbation) go to the
 * wings; refused ones (not finite) are warned about once and the wings keep their own. */
static void apply_inflow(const mjModel *m, mjData *d, int instance, Instance *in,
                         const mjtNum *state) {
  for (size_t p = 0; p < in->inflow_pairs && in->wings; p++) {
    FlapwingInflow now = {0};
    flapwing_wings_inflow(in->wings, p, &now);
    const mjtNum *x = state + NSTATE + 3 * p;
    if (x[0] == now.mean_m_s && x[1] == now.fore_m_s && x[2] == now.left_m_s) continue;
    FlapwingInflow set = {x[0], x[1], x[2]};
    if (flapwing_wings_set_inflow(in->wings, p, set) != FLAPWING_OK && !in->inflow_failing) {
      in->inflow_failing = 1;
      mju_warning("%s (instance %d, body `%s`, t = %.9g s): the inflow states in the plugin "
                  "state were refused: %s; the wings keep their own",
                  PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, in->body_id), d->time,
                  flapwing_last_error());
    }
  }
}

/* A failed init: mju_error with the reason (see the top of the file), then -1 should a user
 * error handler return. */
static int init_failed(const char *fmt, ...) mjPRINTFLIKE(1, 2);
static int init_failed(const char *fmt, ...) {
  char msg[2 * MESSAGE_CHARS];
  va_list args;
  va_start(args, fmt);
  vsnprintf(msg, sizeof(msg), fmt, args);
  va_end(args);
  mju_error("%s", msg);
  return -1;
}

/* The wings' loads are the model's vehicle's: on a body (with what hangs from it) of another
 * mass they accelerate it as many times more or less, which nothing else reports (the
 * dragonfly's wings on examples/mujoco/fly.xml's 1 mg fly made MuJoCo's accelerations blow up
 * at the first step). Warned once per mjData when the masses differ by more than 1%. */
static void warn_mass_mismatch(const mjModel *m, int instance, const Instance *in) {
  FlapwingBodyProperties p;
  if (flapwing_wings_body_properties(in->wings, &p) != FLAPWING_OK) return;
  const double body_kg = m->body_subtreemass[in->body_id];
  if (fabs(body_kg - p.mass_kg) <= 0.01 * p.mass_kg) return;
  mju_warning("%s instance %d: body `%s` (with its subtree) has a mass of %.6g kg and the model "
              "`%s` %.6g kg: the wings' loads are the model's vehicle's, so they accelerate "
              "this body %.3g times as much; give the body the model's mass and inertia "
              "(flapwing_wings_body_properties; examples/mujoco/fly.xml)",
              PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, in->body_id), body_kg,
              in->config.model, p.mass_kg, p.mass_kg / body_kg);
}

/* Frees an instance and all it holds (NULL: nothing). */
static void plugin_free(Instance *in) {
  if (!in) return;
  flapwing_wings_free(in->wings);
  flapwing_wings_free(in->pristine);
  flapwing_wings_free(in->saved);
  fwmj_free_config(&in->config);
  free(in);
}

/* Fails (init_failed: the compiler's load error) on a bad configuration. */
static int plugin_init(const mjModel *m, mjData *d, int instance) {
  char msg[MESSAGE_CHARS];
  int body_id = -1, nbody = 0;
  for (int b = 0; b < m->nbody; b++) {
    if (m->body_plugin[b] == instance) {
      if (body_id < 0) body_id = b;
      nbody++;
    }
  }
  if (nbody != 1) {
    return init_failed("%s instance %d is attached to %d bodies; allowed: exactly one "
                       "(<body><plugin instance=\"...\"/></body>)",
                       PLUGIN_NAME, instance, nbody);
  }
  if (body_id == 0 || m->body_dofnum[body_id] == 0) {
    return init_failed("%s instance %d: body `%s` has no degrees of freedom (the world or a body "
                       "welded to it); allowed: a body with joints (e.g. <freejoint/>)",
                       PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, body_id));
  }
  Instance *in = calloc(1, sizeof(Instance));
  if (!in) {
    return init_failed("%s instance %d: out of memory", PLUGIN_NAME, instance);
  }
  in->body_id = body_id;
  int j = m->body_jntadr[body_id];
  in->free_dof = m->body_jntnum[body_id] == 1 && m->jnt_type[j] == mjJNT_FREE ? m->jnt_dofadr[j] : -1;
  if (in->free_dof >= 0) {
    /* R diag(body_inertia) R^T, R the principal axes' orientation in the body frame. */
    mjtNum r[9];
    mju_quat2Mat(r, m->body_iquat + 4 * body_id);
    const mjtNum *diag = m->body_inertia + 3 * body_id;
    for (int a = 0; a < 3; a++) {
      for (int c = 0; c < 3; c++) {
        double sum = 0.0;
        for (int k = 0; k < 3; k++) sum += r[3 * a + k] * diag[k] * r[3 * c + k];
        in->inertia_body[3 * a + c] = sum;
      }
    }
  }
  if (fwmj_read_config(m, instance, &in->config, msg, sizeof(msg)) != 0 ||
      map_actuators(m, instance, in, msg, sizeof(msg)) != 0 ||
      !(in->wings = instance_wings(in, msg, sizeof(msg)))) {
    fwmj_free_config(&in->config);
    free(in);
    return init_failed("%s instance %d (body `%s`): %s", PLUGIN_NAME, instance,
                       mj_id2name(m, mjOBJ_BODY, body_id), msg);
  }
  in->sent = in->base;
  size_t pairs = 0;
  flapwing_wings_inflow_pairs(in->wings, &pairs);
  const size_t slots = (size_t)(m->plugin_statenum[instance] - NSTATE) / 3;
  in->inflow_pairs = pairs < slots ? pairs : slots;
  write_inflow(in, d->plugin_state + m->plugin_stateadr[instance]);
  warn_mass_mismatch(m, instance, in);
  /* Without the copy a reset rebuilds the wings, as it did before flapwing_wings_clone. */
  if (flapwing_wings_clone(in->wings, &in->pristine) != FLAPWING_OK) in->pristine = NULL;
  if (in->config.rewind && flapwing_wings_clone(in->wings, &in->saved) != FLAPWING_OK) {
    char why[MESSAGE_CHARS];
    snprintf(why, sizeof(why), "%s", flapwing_last_error());
    plugin_free(in);
    return init_failed("%s instance %d (body `%s`): attribute `rewind`: copying the wings: %s",
                       PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, body_id), why);
  }
  d->plugin_data[instance] = (uintptr_t)in;
  return 0;
}

static void plugin_destroy(mjData *d, int instance) {
  plugin_free((Instance *)d->plugin_data[instance]);
  d->plugin_data[instance] = 0;
}

/* mj_resetData: the wings restart from t = 0 (rebuilt if they have stepped). */
static void plugin_reset(const mjModel *m, mjtNum *plugin_state, void *plugin_data, int instance) {
  mju_zero(plugin_state, m->plugin_statenum[instance]);
  Instance *in = (Instance *)plugin_data;
  if (!in) return;
  in->inflow_failing = 0;
  in->stepped = 0;
  in->failing = 0;
  in->time_warned = 0;
  in->saved_steps = UINT64_MAX; /* nothing of this run saved yet */
  memset(&in->wrench, 0, sizeof(in->wrench));
  if (in->wings && in->steps == 0) { /* still at t = 0 */
    write_inflow(in, plugin_state);
    return;
  }
  char msg[MESSAGE_CHARS];
  flapwing_wings_free(in->wings);
  in->steps = 0;
  in->wings = NULL;
  if (in->pristine && flapwing_wings_clone(in->pristine, &in->wings) != FLAPWING_OK) {
    in->wings = NULL;
  }
  if (!in->wings) {
    in->wings = instance_wings(in, msg, sizeof(msg));
    /* Rebuilt: `saved` must be a copy of this build (flapwing_wings_save checks). */
    if (in->wings && in->saved) {
      flapwing_wings_free(in->saved);
      in->saved = NULL;
      if (flapwing_wings_clone(in->wings, &in->saved) != FLAPWING_OK) in->saved = NULL;
    }
  }
  in->sent = in->base;
  in->control_failing = 0;
  write_inflow(in, plugin_state);
  if (!in->wings) {
    mju_warning("%s instance %d: rebuilding the wings on reset failed: %s; the wings apply no "
                "force", PLUGIN_NAME, instance, msg);
  }
}

/* mj_copyData (dest keeps its own instance: MuJoCo restores dest's plugin_data before this
 * call): the copy's wings become a clone of the source's, with the source's step bookkeeping,
 * so that both continue alike from the copied state. The configuration, body and actuator
 * mapping are the model's and already the same. */
static void plugin_copy(mjData *dest, const mjModel *m, const mjData *src, int instance) {
  Instance *to = (Instance *)dest->plugin_data[instance];
  const Instance *from = (const Instance *)src->plugin_data[instance];
  if (!to || !from || to == from) return;
  FlapwingWings *w = NULL;
  if (from->wings && flapwing_wings_clone(from->wings, &w) != FLAPWING_OK) {
    mju_warning("%s instance %d: copying the wings failed: %s; the copy keeps its own wings",
                PLUGIN_NAME, instance, flapwing_last_error());
    /* MuJoCo copied the source's plugin state: put back the copy's own wrench and steps. */
    mjtNum *state = dest->plugin_state + m->plugin_stateadr[instance];
    mju_copy3(state, to->wrench.force_body_n);
    mju_copy3(state + 3, to->wrench.moment_body_nm);
    state[6] = (mjtNum)to->steps;
    write_inflow(to, state);
    return;
  }
  /* The copy's rewind slot must be a copy of the same build as its wings: the source's. */
  FlapwingWings *saved = NULL;
  if (to->saved && from->saved && flapwing_wings_clone(from->saved, &saved) != FLAPWING_OK) {
    saved = NULL;
  }
  flapwing_wings_free(to->wings);
  to->wings = w;
  if (to->saved && saved) {
    flapwing_wings_free(to->saved);
    to->saved = saved;
    to->saved_steps = from->saved_steps;
    to->saved_sent = from->saved_sent;
  } else if (to->saved) {
    /* No copy of the source's slot: start a slot from the copied wings (the copy can go back
     * from its next step on). */
    flapwing_wings_free(to->saved);
    to->saved = NULL;
    if (flapwing_wings_clone(w, &to->saved) != FLAPWING_OK) to->saved = NULL;
    to->saved_steps = UINT64_MAX;
  }
  to->stepped = from->stepped;
  to->steps = from->steps;
  to->failing = from->failing;
  to->wrench = from->wrench;
  to->sent = from->sent;
  to->control_failing = from->control_failing;
  to->time_warned = from->time_warned;
  to->inflow_failing = from->inflow_failing;
}

/* The host set the state to wing step `to` (mj_setState, mjd_transitionFD's perturbed steps)
 * while the wings have taken in->steps: with the `rewind` attribute, one step back is the
 * saved wings (flapwing_wings_restore: the step repeats bit for bit); anything else is warned
 * about once and the wings go on from where they are. */
static void go_back(const mjModel *m, mjData *d, int instance, Instance *in, mjtNum to) {
  if (in->saved && in->wings && to == (mjtNum)in->saved_steps &&
      flapwing_wings_restore(in->wings, in->saved) == FLAPWING_OK) {
    in->steps = in->saved_steps;
    in->sent = in->saved_sent;
    return;
  }
  if (in->time_warned) return;
  in->time_warned = 1;
  const char *why = in->saved
      ? "the host set the state back by more than the one step `rewind` keeps (or forward)"
      : "the host set the state to another step (mj_setState, mjd_transitionFD)";
  const char *advice = in->saved
      ? ""
      : "the attribute rewind=\"true\" has them go back a step with the state, as "
        "mjd_transitionFD needs; ";
  mju_warning("%s (instance %d, body `%s`, t = %.9g s): the plugin state says wing step %.0f "
              "and the wings are at step %llu: %s; the wings go on from where they are, so their "
              "phase no longer follows the body's time (%srestart with mj_resetData; branch a run "
              "with mj_copyData, which copies the wings)",
              PLUGIN_NAME, instance, mj_id2name(m, mjOBJ_BODY, in->body_id), d->time, (double)to,
              (unsigned long long)in->steps, why, advice);
}

/* Passive forces: the wings' wrench on the body at its centre of mass. */
static void plugin_compute(const mjModel *m, mjData *d, int instance, int capability_bit) {
  (void)capability_bit;
  Instance *in = (Instance *)d->plugin_data[instance];
  if (!in) return;
  if (!in->stepped) {
    mjtNum *state = d->plugin_state + m->plugin_stateadr[instance];
    if (state[6] != (mjtNum)in->steps) go_back(m, d, instance, in, state[6]);
    if (in->inflow_pairs) apply_inflow(m, d, instance, in, state);
    if (in->saved && flapwing_wings_save(in->wings, in->saved) == FLAPWING_OK) {
      in->saved_steps = in->steps;
      in->saved_sent = in->sent;
    }
    step_wings(m, d, instance, in);
    in->stepped = 1;
    mju_copy3(state, in->wrench.force_body_n);
    mju_copy3(state + 3, in->wrench.moment_body_nm);
  }
  const int b = in->body_id;
  if (in->free_dof >= 0) {
    free_body_apply(m, d, b, in->free_dof, &in->wrench);
    return;
  }
  /* body frame -> world, applied at the centre of mass */
  const mjtNum *q = d->xquat + 4 * b;
  mjtNum force_world_n[3], moment_world_nm[3];
  mju_rotVecQuat(force_world_n, in->wrench.force_body_n, q);
  mju_rotVecQuat(moment_world_nm, in->wrench.moment_body_nm, q);
  mj_applyFT(m, d, force_world_n, moment_world_nm, d->xipos + 3 * b, b, d->qfrc_passive);
}

/* After MuJoCo's time integration: the next evaluation belongs to a new step. */
static void plugin_advance(const mjModel *m, mjData *d, int instance) {
  Instance *in = (Instance *)d->plugin_data[instance];
  if (!in) return;
  in->stepped = 0;
  /* The state is now at the next step: the wing steps taken and the inflow they start from. */
  mjtNum *state = d->plugin_state + m->plugin_stateadr[instance];
  state[6] = (mjtNum)in->steps;
  if (in->inflow_pairs) write_inflow(in, state);
}

mjPLUGIN_LIB_INIT(flapwing_wings) {
  kAttributes[ATTR_MODEL] = "model";
  kAttributes[ATTR_WIND] = "wind";
  kAttributes[ATTR_TRIM] = "trim";
  kAttributes[ATTR_REWIND] = "rewind";
  for (int i = 0; i < NCONTROL; i++) kAttributes[ATTR_FIRST_CONTROL + i] = kControls[i].name;

  mjpPlugin plugin;
  mjp_defaultPlugin(&plugin);
  plugin.name = PLUGIN_NAME;
  plugin.capabilityflags |= mjPLUGIN_PASSIVE;
  plugin.nattribute = ATTR_FIRST_CONTROL + NCONTROL;
  plugin.attributes = kAttributes;
  plugin.nstate = plugin_nstate;
  plugin.init = plugin_init;
  plugin.destroy = plugin_destroy;
  plugin.reset = plugin_reset;
  plugin.copy = plugin_copy;
  plugin.compute = plugin_compute;
  plugin.advance = plugin_advance;
  mjp_registerPlugin(&plugin);
}
