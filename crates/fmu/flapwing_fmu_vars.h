/* The FMU's variables: one table that both the FMU (flapwing_fmu.c) and the generator of
 * modelDescription.xml (gen_model_description.c) include, so the two cannot disagree. The
 * GUID is a hash of this table: any change to the interface changes it.
 *
 * Frames and units as in flapwing: body x forward, y left, z up, origin at the centre of
 * mass; world z up; SI units; quaternion w, x, y, z (world_from_body). */
#ifndef FLAPWING_FMU_VARS_H
#define FLAPWING_FMU_VARS_H

#include <stdint.h>

#define FLAPWING_FMU_MODEL_IDENTIFIER "flapwing_wings"
#define FLAPWING_FMU_DEFAULT_MODEL "drosophila"

/* Real variables: X(name, value reference, causality, variability, start, unit, description).
 * start is NAN for variables without a start value (calculated ones). Value references run
 * 0, 1, 2, ... in table order. */
#define FLAPWING_FMU_REALS(X)                                                                    \
  X(dt_s, 0, "parameter", "fixed", 0.0, "s",                                                    \
    "Element step; 0 takes the model's own (1 / (f steps_per_wingbeat)), else at most 1 / (20 f)") \
  X(element_dt_s, 1, "calculatedParameter", "fixed", NAN, "s",                                  \
    "Element step in force; communication steps must be whole multiples of it")                 \
  X(position_world_m_x, 2, "input", "continuous", 0.0, "m", "CoM position, world x")            \
  X(position_world_m_y, 3, "input", "continuous", 0.0, "m", "CoM position, world y")            \
  X(position_world_m_z, 4, "input", "continuous", 0.0, "m", "CoM position, world z")            \
  X(world_from_body_w, 5, "input", "continuous", 1.0, "", "Attitude quaternion world_from_body, w") \
  X(world_from_body_x, 6, "input", "continuous", 0.0, "", "Attitude quaternion world_from_body, x") \
  X(world_from_body_y, 7, "input", "continuous", 0.0, "", "Attitude quaternion world_from_body, y") \
  X(world_from_body_z, 8, "input", "continuous", 0.0, "", "Attitude quaternion world_from_body, z") \
  X(velocity_world_m_s_x, 9, "input", "continuous", 0.0, "m/s", "CoM velocity, world x")        \
  X(velocity_world_m_s_y, 10, "input", "continuous", 0.0, "m/s", "CoM velocity, world y")       \
  X(velocity_world_m_s_z, 11, "input", "continuous", 0.0, "m/s", "CoM velocity, world z")       \
  X(angular_velocity_body_rad_s_x, 12, "input", "continuous", 0.0, "rad/s", "Angular velocity, body x") \
  X(angular_velocity_body_rad_s_y, 13, "input", "continuous", 0.0, "rad/s", "Angular velocity, body y") \
  X(angular_velocity_body_rad_s_z, 14, "input", "continuous", 0.0, "rad/s", "Angular velocity, body z") \
  X(control_mean_stroke_rad, 15, "input", "continuous", 0.0, "rad", "Mean stroke angle offset")  \
  X(control_amplitude_rad, 16, "input", "continuous", 0.0, "rad", "Stroke amplitude offset")     \
  X(control_pitch_bias_rad, 17, "input", "continuous", 0.0, "rad", "Pitch bias offset")          \
  X(control_aoa_rad, 18, "input", "continuous", 0.0, "rad", "Mid-stroke angle-of-attack offset") \
  X(control_freq_hz, 19, "input", "continuous", 0.0, "Hz", "Wingbeat frequency offset")          \
  X(control_diff_amplitude_rad, 20, "input", "continuous", 0.0, "rad", "Left-minus-right amplitude") \
  X(control_diff_pitch_bias_rad, 21, "input", "continuous", 0.0, "rad", "Left-minus-right pitch bias") \
  X(control_diff_mean_stroke_rad, 22, "input", "continuous", 0.0, "rad", "Left-minus-right mean stroke angle") \
  X(control_bias_v, 23, "input", "continuous", 0.0, "V", "Drive bias offset (actuated vehicles)") \
  X(control_amplitude_v, 24, "input", "continuous", 0.0, "V", "Drive amplitude offset (actuated vehicles)") \
  X(control_diff_amplitude_v, 25, "input", "continuous", 0.0, "V", "Left-minus-right drive amplitude (actuated vehicles)") \
  X(control_diff_bias_v, 26, "input", "continuous", 0.0, "V", "Left-minus-right drive bias (actuated vehicles)") \
  X(control_diff_second_harmonic, 27, "input", "continuous", 0.0, "", "Left-minus-right second-harmonic fraction (actuated vehicles)") \
  X(force_body_n_x, 28, "output", "continuous", NAN, "N", "Mean wing force and body drag over the last communication step, body x") \
  X(force_body_n_y, 29, "output", "continuous", NAN, "N", "Mean wing force and body drag over the last communication step, body y") \
  X(force_body_n_z, 30, "output", "continuous", NAN, "N", "Mean wing force and body drag over the last communication step, body z") \
  X(moment_body_nm_x, 31, "output", "continuous", NAN, "N.m", "Mean wing moment about the CoM over the last communication step, body x") \
  X(moment_body_nm_y, 32, "output", "continuous", NAN, "N.m", "Mean wing moment about the CoM over the last communication step, body y") \
  X(moment_body_nm_z, 33, "output", "continuous", NAN, "N.m", "Mean wing moment about the CoM over the last communication step, body z") \
  X(trim_forward_speed_m_s, 34, "parameter", "fixed", 0.0, "m/s", "With trim: the flight condition's forward speed (flapsim::flight)") \
  X(trim_climb_rate_m_s, 35, "parameter", "fixed", 0.0, "m/s", "With trim: the flight condition's climb rate") \
  X(trim_world_from_body_w, 36, "calculatedParameter", "fixed", NAN, "", "With trim: the body's attitude at trim, world_from_body, w (NaN without)") \
  X(trim_world_from_body_x, 37, "calculatedParameter", "fixed", NAN, "", "With trim: the body's attitude at trim, world_from_body, x") \
  X(trim_world_from_body_y, 38, "calculatedParameter", "fixed", NAN, "", "With trim: the body's attitude at trim, world_from_body, y") \
  X(trim_world_from_body_z, 39, "calculatedParameter", "fixed", NAN, "", "With trim: the body's attitude at trim, world_from_body, z") \
  X(trim_velocity_world_m_s_x, 40, "calculatedParameter", "fixed", NAN, "m/s", "With trim: the body's velocity at trim, world x") \
  X(trim_velocity_world_m_s_y, 41, "calculatedParameter", "fixed", NAN, "m/s", "With trim: the body's velocity at trim, world y") \
  X(trim_velocity_world_m_s_z, 42, "calculatedParameter", "fixed", NAN, "m/s", "With trim: the body's velocity at trim, world z") \
  X(trim_aero_power_w, 43, "calculatedParameter", "fixed", NAN, "W", "With trim: the wings' cycle-mean aerodynamic power at trim") \
  X(inflow_pair0_mean_m_s, 44, "output", "continuous", NAN, "m/s", "Wing pair 0's dynamic inflow (model [aero] inflow = dynamic; 0 otherwise) after the last communication step: mean induced velocity down through its disc") \
  X(inflow_pair0_fore_m_s, 45, "output", "continuous", NAN, "m/s", "Wing pair 0's dynamic inflow: extra downwash at the disc's front edge") \
  X(inflow_pair0_left_m_s, 46, "output", "continuous", NAN, "m/s", "Wing pair 0's dynamic inflow: extra downwash at the disc's left edge") \
  X(inflow_pair1_mean_m_s, 47, "output", "continuous", NAN, "m/s", "Wing pair 1's (a four-winged model's hind pair) dynamic inflow: mean induced velocity (0 without)") \
  X(inflow_pair1_fore_m_s, 48, "output", "continuous", NAN, "m/s", "Wing pair 1's dynamic inflow: extra downwash at the disc's front edge") \
  X(inflow_pair1_left_m_s, 49, "output", "continuous", NAN, "m/s", "Wing pair 1's dynamic inflow: extra downwash at the disc's left edge")

/* The one String variable (value reference 0) and the one Integer variable (value reference
 * 0), outside the table because there is only one of each. */
#define FLAPWING_FMU_MODEL_DESCRIPTION \
  "Vehicle model: a built-in name (drosophila, bumblebee, robobee_kinematic, robobee, hummingbird, dragonfly) or a path to a model TOML file"
#define FLAPWING_FMU_STEPS_DESCRIPTION "Element steps taken since initialization"
/* The one Boolean variable (value reference 0). */
#define FLAPWING_FMU_TRIM_DESCRIPTION \
  "Trim the wings at the flight condition (trim_forward_speed_m_s, trim_climb_rate_m_s) when the model loads: the control inputs are then offsets from the trimmed controls"

enum {
#define FLAPWING_FMU_VR_ENUM(name, vr, ...) VR_##name = vr,
  FLAPWING_FMU_REALS(FLAPWING_FMU_VR_ENUM)
#undef FLAPWING_FMU_VR_ENUM
  FLAPWING_FMU_N_REALS
};

/* Units used above: name and SI base-unit exponents (kg, m, s, A, rad), for the XML. */
#define FLAPWING_FMU_UNITS(X)  \
  X("s", 0, 0, 1, 0, 0)        \
  X("m", 0, 1, 0, 0, 0)        \
  X("m/s", 0, 1, -1, 0, 0)     \
  X("rad", 0, 0, 0, 0, 1)      \
  X("rad/s", 0, 0, -1, 0, 1)   \
  X("Hz", 0, 0, -1, 0, 0)      \
  X("V", 1, 2, -3, -1, 0)      \
  X("W", 1, 2, -3, 0, 0)       \
  X("N", 1, 1, -2, 0, 0)       \
  X("N.m", 1, 2, -2, 0, 0)

/* The GUID: FNV-1a (64 bit) of the table's text, so the FMU binary and its
 * modelDescription.xml carry the same value exactly when they were built from one table. */
#define FLAPWING_FMU_STR2(x) #x
#define FLAPWING_FMU_STR(x) FLAPWING_FMU_STR2(x)
static const char flapwing_fmu_table_text[] =
    FLAPWING_FMU_STR((FLAPWING_FMU_REALS(FLAPWING_FMU_STR_ROW))) FLAPWING_FMU_MODEL_DESCRIPTION
        FLAPWING_FMU_STEPS_DESCRIPTION FLAPWING_FMU_TRIM_DESCRIPTION FLAPWING_FMU_DEFAULT_MODEL;

static inline void flapwing_fmu_guid(char out[40]) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (const char *p = flapwing_fmu_table_text; *p; p++) {
    h ^= (unsigned char)*p;
    h *= 0x100000001b3ULL;
  }
  static const char hex[] = "0123456789abcdef";
  const char *prefix = "{flapwing-wings-";
  int i = 0;
  for (; prefix[i]; i++) out[i] = prefix[i];
  for (int k = 15; k >= 0; k--) out[i++] = hex[(h >> (4 * k)) & 0xf];
  out[i++] = '}';
  out[i] = '\0';
}

#endif
