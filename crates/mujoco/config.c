/* config.c: reading the `flapwing.wings` plugin's configuration attributes (config.h). */

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"

/* Rust's f64::to_radians factor (core::f64::consts::PI / 180), so values match flapwing's. */
#define PI_RAD 3.14159265358979323846
#define DEG_TO_RAD (PI_RAD / 180.0)

const ControlAttribute kControls[NCONTROL] = {
  {"mean_stroke_deg", "mean_stroke_rad", offsetof(FlapwingControls, mean_stroke_rad), DEG_TO_RAD},
  {"amplitude_deg", "amplitude_rad", offsetof(FlapwingControls, amplitude_rad), DEG_TO_RAD},
  {"pitch_bias_deg", "pitch_bias_rad", offsetof(FlapwingControls, pitch_bias_rad), DEG_TO_RAD},
  {"aoa_deg", "aoa_rad", offsetof(FlapwingControls, aoa_rad), DEG_TO_RAD},
  {"freq_hz", "freq_hz", offsetof(FlapwingControls, freq_hz), 1.0},
  {"diff_amplitude_deg", "diff_amplitude_rad", offsetof(FlapwingControls, diff_amplitude_rad), DEG_TO_RAD},
  {"diff_pitch_bias_deg", "diff_pitch_bias_rad", offsetof(FlapwingControls, diff_pitch_bias_rad), DEG_TO_RAD},
  {"diff_mean_stroke_deg", "diff_mean_stroke_rad", offsetof(FlapwingControls, diff_mean_stroke_rad), DEG_TO_RAD},
  {"bias_v", "bias_v", offsetof(FlapwingControls, bias_v), 1.0},
  {"amplitude_v", "amplitude_v", offsetof(FlapwingControls, amplitude_v), 1.0},
  {"diff_amplitude_v", "diff_amplitude_v", offsetof(FlapwingControls, diff_amplitude_v), 1.0},
  {"diff_bias_v", "diff_bias_v", offsetof(FlapwingControls, diff_bias_v), 1.0},
  {"diff_second_harmonic", "diff_second_harmonic", offsetof(FlapwingControls, diff_second_harmonic), 1.0},
};
_Static_assert(sizeof(kControls) / sizeof(kControls[0]) == NCONTROL, "NCONTROL is kControls' length");

const char *kAttributes[ATTR_FIRST_CONTROL + NCONTROL];

/* The attribute's text, or NULL if absent or empty. */
static const char *attribute(const mjModel *m, int instance, const char *name) {
  const char *s = mj_getPluginConfig(m, instance, name);
  return (s && s[0]) ? s : NULL;
}

/* Parses `n` finite numbers separated by white space; 0 on success. */
static int parse_numbers(const char *text, double *out, int n) {
  const char *p = text;
  for (int i = 0; i < n; i++) {
    char *end;
    errno = 0;
    double x = strtod(p, &end);
    if (end == p || errno == ERANGE || !isfinite(x)) return -1;
    out[i] = x;
    p = end;
  }
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') p++;
  return *p ? -1 : 0;
}

void fwmj_free_config(Config *c) {
  free(c->model);
  c->model = NULL;
}

/* Reads the instance's attributes; on failure writes a message and returns -1. */
int fwmj_read_config(const mjModel *m, int instance, Config *c, char *msg, size_t nmsg) {
  memset(c, 0, sizeof(*c));
  c->dt_s = m->opt.timestep;
  /* The C ABI reads a step of 0 as "the model's own": the wings would advance while MuJoCo's
   * clock stands still. The upper bound (1/10 of the wingbeat) is the wing set's own. */
  if (!(c->dt_s > 0.0) || !isfinite(c->dt_s)) {
    snprintf(msg, nmsg,
             "<option timestep> = %.17g s; allowed: a finite step > 0 s of at most 1/10 of the "
             "wingbeat period (the wings advance by it at every mj_step)",
             c->dt_s);
    return -1;
  }
  const char *model = attribute(m, instance, "model");
  if (!model) {
    snprintf(msg, nmsg,
             "attribute `model` is missing or empty; allowed: a built-in model name "
             "(drosophila, bumblebee, robobee_kinematic, dragonfly, robobee, hummingbird) or a TOML file path");
    return -1;
  }
  c->model = malloc(strlen(model) + 1);
  if (!c->model) {
    snprintf(msg, nmsg, "out of memory copying attribute `model`");
    return -1;
  }
  strcpy(c->model, model);

  const char *wind = attribute(m, instance, "wind");
  if (wind) {
    if (parse_numbers(wind, c->wind_world_m_s, 3) != 0) {
      snprintf(msg, nmsg,
               "attribute `wind` = \"%s\"; allowed: three finite numbers, the world-frame wind in m/s",
               wind);
      return -1;
    }
    c->has_wind = 1;
  }

  const char *trim = attribute(m, instance, "trim");
  if (trim) {
    if (parse_numbers(trim, c->trim_m_s, 2) != 0) {
      snprintf(msg, nmsg,
               "attribute `trim` = \"%s\"; allowed: two finite numbers, the forward speed and "
               "climb rate in m/s to trim at (0 0: hover)",
               trim);
      return -1;
    }
    c->has_trim = 1;
  }

  const char *rewind = attribute(m, instance, "rewind");
  if (rewind) {
    if (strcmp(rewind, "true") == 0) {
      c->rewind = 1;
    } else if (strcmp(rewind, "false") != 0) {
      snprintf(msg, nmsg,
               "attribute `rewind` = \"%s\"; allowed: \"true\" (the wings go back a step with the "
               "state: mjd_transitionFD; a save before every step) or \"false\" (the default)",
               rewind);
      return -1;
    }
  }

  for (int i = 0; i < NCONTROL; i++) {
    const char *text = attribute(m, instance, kControls[i].name);
    if (!text) continue;
    double x;
    if (parse_numbers(text, &x, 1) != 0) {
      snprintf(msg, nmsg, "attribute `%s` = \"%s\"; allowed: one finite number", kControls[i].name,
               text);
      return -1;
    }
    *(double *)((char *)&c->controls + kControls[i].offset) = x * kControls[i].to_si;
    c->has_control[i] = 1;
  }
  return 0;
}
