/* The twin's cycle in C: the joint drives' per-cycle set-up, the cycle's physics steps and
 * what the checks need from them, in one call (sim/native_drives.py loads it, sim/servo.py
 * is its Python face and its fallback: both compute the same numbers).
 *
 * Why C: the work around the one mj_step(nstep=8) of a cycle is ~30 arithmetic operations
 * on 6-vectors; in numpy each of them costs a microsecond of interpreter and call overhead,
 * together more than half of MuJoCo's own cost per cycle. Here it is a few hundred
 * nanoseconds, and the interpreter lock is released for the whole cycle.
 *
 * The drives (sim/servo.py has the physics): actuators 0..5 are position loops whose
 * reference is their integrator state (act), driven by the setpoint velocity (ctrl 0..5);
 * actuators 6..11 are feed-forward motors (ctrl 6..11). Gains are accelerations scaled by
 * the diagonal of the joint-space inertia at the cycle's start.
 *
 * Units: rad, rad/s, rad/s^2, N·m, s.
 */
#include <math.h>

#include <mujoco/mujoco.h>

#define JD_JOINTS 6

/* Field for field the _Drives structure of native_drives.py. */
typedef struct {
  /* constant: gains (1/s^2, 1/s), joint friction (N·m·s/rad), drag damping of a released
   * arm (N·m·s/rad), cycle (s), where each inertia diagonal sits in d->M, steps per cycle */
  double kp[JD_JOINTS], kd[JD_JOINTS], damping[JD_JOINTS];
  double drag_damping, cycle;
  int diag[JD_JOINTS];
  int steps;
  /* set by Python between cycles: drag mode (gravity compensation only) */
  int released;
  /* the setpoints: reference at the cycle's start, setpoint at its end, their velocity and
   * its change since the last cycle */
  double from[JD_JOINTS], to[JD_JOINTS], velocity[JD_JOINTS], accel[JD_JOINTS];
  /* the setpoint jd_new_setpoint adopts (rad), written there by Python */
  double next[JD_JOINTS];
  /* results of the last cycle: drive torques (N·m), the largest following error (rad) and
   * its joint */
  double tau[JD_JOINTS];
  double lag;
  int lag_joint;
} jd_drives;

int jd_drives_size(void) { return (int)sizeof(jd_drives); }

/* The MuJoCo version this library was compiled against (mjVERSION_HEADER): the loader
 * refuses a library built for another MuJoCo, whose structures may be laid out otherwise. */
int jd_mujoco_version(void) { return mjVERSION_HEADER; }

/* Adopt s->next (rad) as the setpoint to reach at the end of the next cycle. */
void jd_new_setpoint(jd_drives* s) {
  for (int i = 0; i < JD_JOINTS; i++) {
    double velocity = (s->next[i] - s->to[i]) / s->cycle;
    s->accel[i] = (velocity - s->velocity[i]) / s->cycle;
    s->velocity[i] = velocity;
    s->from[i] = s->to[i];
    s->to[i] = s->next[i];
  }
}

/* Write the cycle's gains, feed-forward and reference, step the cycle, record the drive
 * torques and the following error against the setpoint. Gains go into the model (m is
 * changed: it belongs to the twin alone). */
void jd_cycle(mjModel* m, mjData* d, jd_drives* s) {
  double* gain = m->actuator_gainprm;
  double* bias = m->actuator_biasprm;
  double* ff = d->ctrl + JD_JOINTS;
  if (s->released) {
    for (int i = 0; i < JD_JOINTS; i++) {
      gain[i * mjNGAIN] = 0.0;
      bias[i * mjNBIAS + 1] = 0.0;
      bias[i * mjNBIAS + 2] = -s->drag_damping;
      ff[i] = 0.0;
    }
  } else {
    double kv[JD_JOINTS];
    for (int i = 0; i < JD_JOINTS; i++) {
      double inertia = d->M[s->diag[i]];
      gain[i * mjNGAIN] = s->kp[i] * inertia;
      bias[i * mjNBIAS + 1] = -gain[i * mjNGAIN];
      kv[i] = s->kd[i] * inertia;
      bias[i * mjNBIAS + 2] = -kv[i];
    }
    if (m->nv == JD_JOINTS) {
      mj_mulM(m, d, ff, s->accel);    /* M(q)·q̈_sp; nv is 6, the arm's joints */
    } else {
      /* a tool's fingers or the scene's parts add degrees of freedom after the arm's: the
       * arm's rows of M·(q̈_sp, 0) */
      mj_markStack(d);
      mjtNum* accel = mj_stackAllocNum(d, m->nv);
      mjtNum* full = mj_stackAllocNum(d, m->nv);
      mju_zero(accel, m->nv);
      mju_copy(accel, s->accel, JD_JOINTS);
      mj_mulM(m, d, full, accel);
      mju_copy(ff, full, JD_JOINTS);
      mj_freeStack(d);
    }
    /* + the damping's and the joint friction's share of the setpoint velocity, and the
     * Coriolis and centrifugal torques (the bias less the gravity MuJoCo compensates) */
    for (int i = 0; i < JD_JOINTS; i++)
      ff[i] += (kv[i] + s->damping[i]) * s->velocity[i] + d->qfrc_bias[i]
               - d->qfrc_gravcomp[i];
  }
  for (int i = 0; i < JD_JOINTS; i++) {
    d->act[i] = s->from[i];
    d->ctrl[i] = s->velocity[i];
  }
  for (int k = 0; k < s->steps; k++)
    mj_step(m, d);
  s->lag = -1.0;
  s->lag_joint = 0;
  for (int i = 0; i < JD_JOINTS; i++) {
    double lag = fabs(s->to[i] - d->qpos[i]);
    s->tau[i] = d->qfrc_actuator[i];
    if (lag > s->lag) {
      s->lag = lag;
      s->lag_joint = i;
    }
  }
}
