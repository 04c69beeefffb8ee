/* config.h: the `flapwing.wings` plugin's configuration attributes (crates/mujoco): their
 * names and units, what an instance was configured with, and reading them from the model. */

#ifndef FLAPWING_MUJOCO_CONFIG_H
#define FLAPWING_MUJOCO_CONFIG_H

#include <stddef.h>

#include <mujoco/mujoco.h>

#include "flapwing.h"

/* Shared between the plugin's files, kept out of its dynamic symbol table. */
#define FWMJ_HIDDEN __attribute__((visibility("hidden")))

/* Config attributes. Controls are offsets on the model's base kinematics (flapsim::Controls);
 * angles in degrees here, converted to radians as the TOML models' [controls] are. */
enum {
  ATTR_MODEL = 0,
  ATTR_WIND,
  ATTR_TRIM,
  ATTR_REWIND,
  ATTR_FIRST_CONTROL, /* the controls, in the order of kControls below */
};

typedef struct ControlAttribute {
  const char *name;   /* the config attribute (degrees for angles) */
  const char *si;     /* the field's SI name: an actuator `<instance>:<si>` drives it */
  size_t offset;      /* of the double in FlapwingControls */
  double to_si;       /* factor to SI (rad per degree, or 1) */
} ControlAttribute;

/* The control attributes (kControls). */
#define NCONTROL 13

FWMJ_HIDDEN extern const ControlAttribute kControls[NCONTROL];

/* Every attribute's name, in the order above (filled at registration). */
FWMJ_HIDDEN extern const char *kAttributes[ATTR_FIRST_CONTROL + NCONTROL];

/* What an instance was configured with (kept to rebuild the wings on reset). */
typedef struct Config {
  char *model;                  /* built-in name or TOML path */
  int has_control[NCONTROL];    /* which control attributes were given */
  FlapwingControls controls;    /* SI; the given fields (the rest keep the model's) */
  int has_wind;
  double wind_world_m_s[3];
  int has_trim;
  double trim_m_s[2];           /* flight condition to trim at: forward speed, climb rate */
  int rewind;                   /* save the wings before every step, so that a host that sets
                                 * the state back a step (mjd_transitionFD) has them go back */
  double dt_s;                  /* m->opt.timestep */
} Config;

/* Reads the instance's attributes into `c`; on failure writes a message and returns -1. */
FWMJ_HIDDEN int fwmj_read_config(const mjModel *m, int instance, Config *c, char *msg,
                                 size_t nmsg);

/* Frees what fwmj_read_config allocated. */
FWMJ_HIDDEN void fwmj_free_config(Config *c);

#endif
