/* The seeded IK of a JAKA arm in one compiled call: the fast path of
 * jaka_driver.kinematics.Kinematics.ik, for the Python side to call through ctypes. For the
 * Zu structure, jk_ik_seeded; for the others (no compiled closed form), jk_local_seeded.
 *
 * Same algorithm as the Python path, step for step: the closed form of the ideal Zu chain
 * (UR-type; the model's own lengths, its goal turned by `tip` into the ideal chain's joint-6
 * frame) picks the solution nearest the reference (each joint at the 2pi-turn nearest to it,
 * distance weighted by 1/max_velocity), then Newton steps on log6 of the joint-6 pose error with the
 * LOCAL joint-6 Jacobian of the exact chain (the URDF's joint placements) remove the URDF's
 * departures from the ideal chain. Anything unusual (no closed-form solution, a singular step,
 * no convergence in 4 steps) returns 0 and the Python path, which also explains failures,
 * takes over.
 *
 * Units: m, rad. Matrices are row-major. Frames: every pose is that of the joint-6 frame in
 * the base frame; tcp_offset (joint 6 -> TCP, m, joint-6 frame) only weighs the error.
 */
#include <math.h>
#include <string.h>

typedef struct {
    double R[6][9];             /* joint placement rotations in the parent joint frame, each
                                   joint turning about its frame's z */
    double t[6][3];             /* joint placement translations, m */
    double fix6[12];            /* the model's joint-6 frame in the last frame of R/t (3x4
                                   row-major: rotation | translation): a joint-6 axis that is
                                   not z in the file is re-expressed as z above */
    double tip[12];             /* ideal chain's joint-6 frame in the model's (3x4): the
                                   closed form solves goal * tip */
    double a2, a3, d4, d5, d6;  /* ideal Zu-chain lengths, m */
    double shoulder[3];         /* ideal joint-1 frame origin in the base, m */
    double lo[6], hi[6];        /* joint limits, rad */
    double w2[6];               /* (1 / max_velocity)^2, (s/rad)^2 */
} jk_chain;

#define TWO_PI 6.283185307179586
#define MAX_STEP2 0.04          /* rad^2: a longer Newton step means a singular spot */
#define MAX_STEPS 4
#define SLACK 2e-3              /* m, rad: the file's departure from the ideal chain
                                   (closed_form.py) */
#define SETTLED_STEP2 1e-9      /* rad^2: a longer step is followed by one more (numeric.py) */

static double clampd(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* Joint x at the 2pi-turn nearest to r, else the one a turn away, inside [lo, hi]; a turn
 * beyond a limit by no more than SLACK (the ideal chain's error) is put on the limit; 0 if
 * none. */
static int near_turn(const jk_chain *c, double x, int j, double r, double *out) {
    double m = fmod(x - r + M_PI, TWO_PI);
    if (m < 0) m += TWO_PI;
    double v = r + m - M_PI;
    double turns[2] = {v, v > r ? v - TWO_PI : v + TWO_PI};
    for (int k = 0; k < 2; k++)
        if (turns[k] >= c->lo[j] - SLACK && turns[k] <= c->hi[j] + SLACK) {
            *out = clampd(turns[k], c->lo[j], c->hi[j]);
            return 1;
        }
    return 0;
}

/* Nearest closed-form solution for the joint-6 pose T (4x4); 0 if none within limits. */
static int closed_form(const jk_chain *c, const double *T, const double *ref, double q[6]) {
    const double xx = T[0], yx = T[1], zx = T[2], px = T[3];
    const double xy = T[4], yy = T[5], zy = T[6], py = T[7];
    const double xz = T[8], yz = T[9], zz = T[10], pz = T[11];
    const double *w2 = c->w2;
    double p5x = px - c->shoulder[0] - c->d6 * zx;
    double p5y = py - c->shoulder[1] - c->d6 * zy;
    double p5z = pz - c->shoulder[2] - c->d6 * zz;
    double r = hypot(p5x, p5y);
    if (r < c->d4 - SLACK) return 0;
    const double c3_slack = SLACK * (c->a2 + c->a3) / (c->a2 * c->a3);
    double phi = atan2(p5y, p5x), alpha = asin(fmin(c->d4 / r, 1.0));
    double best = INFINITY;
    double q1s[2] = {phi - alpha, phi + alpha - M_PI};
    for (int i1 = 0; i1 < 2; i1++) {
        double q1 = q1s[i1], v1;
        if (!near_turn(c, q1, 0, ref[0], &v1)) continue;
        double dist1 = w2[0] * (v1 - ref[0]) * (v1 - ref[0]);
        if (dist1 >= best) continue;
        double c1 = cos(q1), s1 = sin(q1);
        double c5 = clampd(s1 * zx - c1 * zy, -1.0, 1.0);
        double xy1 = c1 * xy - s1 * xx, yy1 = c1 * yy - s1 * yx;
        double q5a = acos(c5);
        double q5s[2] = {q5a, -q5a};
        int n5 = q5a > 1e-12 ? 2 : 1;
        if (n5 == 1) q5s[0] = 0.0;
        for (int i5 = 0; i5 < n5; i5++) {
            double q5 = q5s[i5], s5 = sin(q5);
            double q6 = s5 > 1e-4 ? atan2(yy1, -xy1) : (s5 < -1e-4 ? atan2(-yy1, xy1) : ref[5]);
            double v5, v6;
            if (!near_turn(c, q5, 4, ref[4], &v5) || !near_turn(c, q6, 5, ref[5], &v6)) continue;
            double dist56 = dist1 + w2[4] * (v5 - ref[4]) * (v5 - ref[4])
                            + w2[5] * (v6 - ref[5]) * (v6 - ref[5]);
            if (dist56 >= best) continue;
            double c6 = cos(q6), s6 = sin(q6);
            double y4x = s6 * xx + c6 * yx, y4y = s6 * xy + c6 * yy, y4z = s6 * xz + c6 * yz;
            double q234 = atan2(-(c1 * y4x + s1 * y4y), y4z);
            double u = c1 * (p5x + c->d5 * y4x) + s1 * (p5y + c->d5 * y4y);
            double v = p5z + c->d5 * y4z;
            double c3 = (u * u + v * v - c->a2 * c->a2 - c->a3 * c->a3) / (2.0 * c->a2 * c->a3);
            if (fabs(c3) > 1.0 + c3_slack) continue;
            double q3a = acos(clampd(c3, -1.0, 1.0));
            double q3s[2] = {q3a, -q3a};
            int n3 = q3a > 1e-12 ? 2 : 1;
            if (n3 == 1) q3s[0] = 0.0;
            for (int i3 = 0; i3 < n3; i3++) {
                double q3 = q3s[i3];
                double q2 = atan2(v, u) - atan2(c->a3 * sin(q3), c->a2 + c->a3 * c3);
                double v2, v3, v4;
                if (!near_turn(c, q2, 1, ref[1], &v2) || !near_turn(c, q3, 2, ref[2], &v3)
                    || !near_turn(c, q234 - q2 - q3, 3, ref[3], &v4)) continue;
                double dist = dist56 + w2[1] * (v2 - ref[1]) * (v2 - ref[1])
                              + w2[2] * (v3 - ref[2]) * (v3 - ref[2])
                              + w2[3] * (v4 - ref[3]) * (v4 - ref[3]);
                if (dist < best) {
                    best = dist;
                    q[0] = v1; q[1] = v2; q[2] = v3; q[3] = v4; q[4] = v5; q[5] = v6;
                }
            }
        }
    }
    return best < INFINITY;
}

/* Joint frames in the base: rotation R (row-major) and origin p of each joint after its
 * rotation, the joint axis the frame's z; and the model's joint-6 frame (R6, p6). */
static void forward(const jk_chain *c, const double q[6], double R[6][9], double p[6][3],
                    double R6[9], double p6[3]) {
    double Rp[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, pp[3] = {0, 0, 0};
    for (int i = 0; i < 6; i++) {
        const double *Ri = c->R[i], *ti = c->t[i];
        double B[9];
        for (int r = 0; r < 3; r++) {
            p[i][r] = pp[r] + Rp[3 * r] * ti[0] + Rp[3 * r + 1] * ti[1] + Rp[3 * r + 2] * ti[2];
            for (int k = 0; k < 3; k++)
                B[3 * r + k] = Rp[3 * r] * Ri[k] + Rp[3 * r + 1] * Ri[3 + k]
                               + Rp[3 * r + 2] * Ri[6 + k];
        }
        double cq = cos(q[i]), sq = sin(q[i]);
        for (int r = 0; r < 3; r++) {   /* B * Rz(q) */
            R[i][3 * r] = B[3 * r] * cq + B[3 * r + 1] * sq;
            R[i][3 * r + 1] = -B[3 * r] * sq + B[3 * r + 1] * cq;
            R[i][3 * r + 2] = B[3 * r + 2];
        }
        memcpy(Rp, R[i], sizeof Rp);
        memcpy(pp, p[i], sizeof pp);
    }
    const double *f = c->fix6;
    for (int r = 0; r < 3; r++) {
        p6[r] = pp[r] + Rp[3 * r] * f[3] + Rp[3 * r + 1] * f[7] + Rp[3 * r + 2] * f[11];
        for (int k = 0; k < 3; k++)
            R6[3 * r + k] = Rp[3 * r] * f[k] + Rp[3 * r + 1] * f[4 + k] + Rp[3 * r + 2] * f[8 + k];
    }
}

/* G = T * tip, both 4x4 row-major poses (tip given as 3x4). */
static void times_tip(const jk_chain *c, const double *T, double G[16]) {
    const double *k = c->tip;
    for (int r = 0; r < 3; r++) {
        for (int j = 0; j < 4; j++)
            G[4 * r + j] = T[4 * r] * k[j] + T[4 * r + 1] * k[4 + j] + T[4 * r + 2] * k[8 + j]
                           + (j == 3 ? T[4 * r + 3] : 0.0);
    }
    G[12] = G[13] = G[14] = 0.0;
    G[15] = 1.0;
}

/* E = M6^-1 * goal: rotation E (row-major) and translation e. */
static void pose_error(const double *R6, const double *p6, const double *T, double E[9],
                       double e[3]) {
    double d[3] = {T[3] - p6[0], T[7] - p6[1], T[11] - p6[2]};
    for (int r = 0; r < 3; r++) {
        e[r] = R6[r] * d[0] + R6[3 + r] * d[1] + R6[6 + r] * d[2];
        for (int k = 0; k < 3; k++)
            E[3 * r + k] = R6[r] * T[k] + R6[3 + r] * T[4 + k] + R6[6 + r] * T[8 + k];
    }
}

/* Position (m) and rotation (rad) error at the TCP, as Kinematics._tcp_error. */
static void tcp_error(const double E[9], const double e[3], const double *off, double *pe,
                      double *re) {
    double x = e[0], y = e[1], z = e[2];
    if (off) {
        x += (E[0] - 1.0) * off[0] + E[1] * off[1] + E[2] * off[2];
        y += E[3] * off[0] + (E[4] - 1.0) * off[1] + E[5] * off[2];
        z += E[6] * off[0] + E[7] * off[1] + (E[8] - 1.0) * off[2];
    }
    double s = 0.5 * sqrt((E[7] - E[5]) * (E[7] - E[5]) + (E[2] - E[6]) * (E[2] - E[6])
                          + (E[3] - E[1]) * (E[3] - E[1]));
    *pe = sqrt(x * x + y * y + z * z);
    *re = atan2(s, 0.5 * (E[0] + E[4] + E[8] - 1.0));
}

/* log6 of (E, e) as Pinocchio's: [v; w]. 0 near a half turn (the caller falls back). */
static int log6(const double E[9], const double e[3], double out[6]) {
    double vx = E[7] - E[5], vy = E[2] - E[6], vz = E[3] - E[1];
    double s = 0.5 * sqrt(vx * vx + vy * vy + vz * vz);
    double th = atan2(s, 0.5 * (E[0] + E[4] + E[8] - 1.0));
    if (th > 3.0) return 0;
    double k = th < 1e-8 ? 0.5 : 0.5 * th / sin(th);
    double w[3] = {k * vx, k * vy, k * vz};
    double alpha, beta;
    if (th < 1e-4) {
        alpha = 1.0 - th * th / 12.0;
        beta = 1.0 / 12.0 + th * th / 720.0;
    } else {
        double t2 = th * th, cth = cos(th), sth = sin(th);
        alpha = th * sth / (2.0 * (1.0 - cth));
        beta = 1.0 / t2 - sth / (2.0 * th * (1.0 - cth));
    }
    double wp = w[0] * e[0] + w[1] * e[1] + w[2] * e[2];
    double cx = w[1] * e[2] - w[2] * e[1], cy = w[2] * e[0] - w[0] * e[2],
           cz = w[0] * e[1] - w[1] * e[0];
    out[0] = alpha * e[0] - 0.5 * cx + beta * wp * w[0];
    out[1] = alpha * e[1] - 0.5 * cy + beta * wp * w[1];
    out[2] = alpha * e[2] - 0.5 * cz + beta * wp * w[2];
    out[3] = w[0]; out[4] = w[1]; out[5] = w[2];
    return 1;
}

/* Solve A x = b (6x6, row-major, destroyed) by Gaussian elimination with partial pivoting. */
static int solve6(double A[36], double b[6]) {
    for (int col = 0; col < 6; col++) {
        int piv = col;
        for (int r = col + 1; r < 6; r++)
            if (fabs(A[6 * r + col]) > fabs(A[6 * piv + col])) piv = r;
        if (fabs(A[6 * piv + col]) < 1e-12) return 0;
        if (piv != col) {
            for (int k = 0; k < 6; k++) {
                double tmp = A[6 * col + k]; A[6 * col + k] = A[6 * piv + k]; A[6 * piv + k] = tmp;
            }
            double tmp = b[col]; b[col] = b[piv]; b[piv] = tmp;
        }
        for (int r = col + 1; r < 6; r++) {
            double f = A[6 * r + col] / A[6 * col + col];
            for (int k = col; k < 6; k++) A[6 * r + k] -= f * A[6 * col + k];
            b[r] -= f * b[col];
        }
    }
    for (int r = 5; r >= 0; r--) {
        double acc = b[r];
        for (int k = r + 1; k < 6; k++) acc -= A[6 * r + k] * b[k];
        b[r] = acc / A[6 * r + r];
    }
    return 1;
}

/* LOCAL Jacobian of the joint-6 frame (R6, p6) (rows v, w in that frame; column k = joint k). */
static void jacobian6(double R[6][9], double p[6][3], const double R6[9], const double p6[3],
                      double J[36]) {
    for (int k = 0; k < 6; k++) {
        double z[3] = {R[k][2], R[k][5], R[k][8]};
        double d[3] = {p6[0] - p[k][0], p6[1] - p[k][1], p6[2] - p[k][2]};
        double lin[3] = {z[1] * d[2] - z[2] * d[1], z[2] * d[0] - z[0] * d[2],
                         z[0] * d[1] - z[1] * d[0]};
        for (int r = 0; r < 3; r++) {
            J[6 * r + k] = R6[r] * lin[0] + R6[3 + r] * lin[1] + R6[6 + r] * lin[2];
            J[6 * (r + 3) + k] = R6[r] * z[0] + R6[3 + r] * z[1] + R6[6 + r] * z[2];
        }
    }
}

/* Smallest singular value of the 6x6 matrix A (row-major; destroyed): one-sided Jacobi
 * (Hestenes) rotates pairs of columns until every pair is orthogonal to rounding; the singular
 * values are then the columns' lengths. Accurate to rounding relative to the largest, as
 * LAPACK's SVD, which the Python path (numpy.linalg.svd) uses. */
static double smallest_singular_value(double A[36]) {
    for (int sweep = 0; sweep < 40; sweep++) {
        int rotated = 0;
        for (int i = 0; i < 5; i++)
            for (int j = i + 1; j < 6; j++) {
                double a = 0.0, b = 0.0, g = 0.0;
                for (int r = 0; r < 6; r++) {
                    double x = A[6 * r + i], y = A[6 * r + j];
                    a += x * x;
                    b += y * y;
                    g += x * y;
                }
                if (fabs(g) <= 1e-15 * sqrt(a * b)) continue;
                rotated = 1;
                double zeta = (b - a) / (2.0 * g);
                double t = (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
                double cs = 1.0 / sqrt(1.0 + t * t), sn = cs * t;
                for (int r = 0; r < 6; r++) {
                    double x = A[6 * r + i], y = A[6 * r + j];
                    A[6 * r + i] = cs * x - sn * y;
                    A[6 * r + j] = sn * x + cs * y;
                }
            }
        if (!rotated) break;
    }
    double least = INFINITY;
    for (int k = 0; k < 6; k++) {
        double s = 0.0;
        for (int r = 0; r < 6; r++) s += A[6 * r + k] * A[6 * r + k];
        if (s < least) least = s;
    }
    return sqrt(least);
}

/* Newton steps from q (as numeric.NumericIk.polish): T the joint-6 goal, at most max_steps,
 * until the TCP error is within tolerance and the last step settled the joints. On success
 * returns the number of steps (>= 1), q updated and err = (position m, rotation rad); else 0. */
static int newton(const jk_chain *c, const double *T, const double *tcp_offset, double pos_tol,
                  double rot_tol, int max_steps, double q[6], double *err) {
    double R[6][9], p[6][3], R6[9], p6[3], E[9], e[3], J[36], dq[6];
    double pe = INFINITY, re = INFINITY;
    for (int it = 1; it <= max_steps; it++) {
        forward(c, q, R, p, R6, p6);
        pose_error(R6, p6, T, E, e);
        if (!log6(E, e, dq)) return 0;
        jacobian6(R, p, R6, p6, J);
        if (!solve6(J, dq)) return 0;
        double step2 = 0.0;
        for (int k = 0; k < 6; k++) step2 += dq[k] * dq[k];
        if (!(step2 < MAX_STEP2)) return 0;
        for (int k = 0; k < 6; k++) q[k] += dq[k];
        forward(c, q, R, p, R6, p6);
        pose_error(R6, p6, T, E, e);
        tcp_error(E, e, tcp_offset, &pe, &re);
        if (pe <= pos_tol && re <= rot_tol && (step2 <= SETTLED_STEP2 || it == max_steps)) {
            int clipped = 0;
            for (int k = 0; k < 6; k++) {
                if (q[k] < c->lo[k]) { q[k] = c->lo[k]; clipped = 1; }
                if (q[k] > c->hi[k]) { q[k] = c->hi[k]; clipped = 1; }
            }
            if (clipped) {      /* a joint on its limit stepped just past it */
                forward(c, q, R, p, R6, p6);
                pose_error(R6, p6, T, E, e);
                tcp_error(E, e, tcp_offset, &pe, &re);
                if (!(pe <= pos_tol && re <= rot_tol)) return 0;
            }
            err[0] = pe;
            err[1] = re;
            return it;
        }
    }
    return 0;
}

/* The fast path of Kinematics.ik. T: joint-6 goal (4x4 row-major, m); ref: reference joints
 * (rad, inside the limits); tcp_offset: 3 values or NULL. On success returns the number of
 * Newton steps (>= 1) and writes q (rad) and err = (position m, rotation rad); else 0. */
int jk_ik(const jk_chain *c, const double *T, const double *ref, const double *tcp_offset,
          double pos_tol, double rot_tol, double *q, double *err) {
    double G[16];
    times_tip(c, T, G);
    if (!closed_form(c, G, ref, q)) return 0;
    return newton(c, T, tcp_offset, pos_tol, rot_tol, MAX_STEPS, q, err);
}

/* Damped least squares from q (as numeric.NumericIk.dls, no TCP offset): steps
 * J^T (J J^T + (|e|^2 + 1e-12) I)^-1 e on log6 e of the joint-6 error, at most 0.5 rad long,
 * each clamped into the limits, until the error is within tolerance; at most max_iter steps.
 * Returns the steps taken + 1 on success (q updated, err written), else 0. */
static int dls(const jk_chain *c, const double *T, double pos_tol, double rot_tol,
               int max_iter, double q[6], double *err) {
    double R[6][9], p[6][3], R6[9], p6[3], E[9], e[3], J[36], A[36], y[6];
    for (int k = 0; k < 6; k++) q[k] = clampd(q[k], c->lo[k], c->hi[k]);
    for (int it = 0; it <= max_iter; it++) {
        double pe, re;
        forward(c, q, R, p, R6, p6);
        pose_error(R6, p6, T, E, e);
        tcp_error(E, e, NULL, &pe, &re);
        if (pe <= pos_tol && re <= rot_tol) {
            err[0] = pe;
            err[1] = re;
            return it + 1;
        }
        if (it == max_iter || !log6(E, e, y)) return 0;
        jacobian6(R, p, R6, p6, J);
        double damping = 1e-12;
        for (int k = 0; k < 6; k++) damping += y[k] * y[k];
        for (int r = 0; r < 6; r++)
            for (int k = 0; k < 6; k++) {
                double s = r == k ? damping : 0.0;
                for (int m = 0; m < 6; m++) s += J[6 * r + m] * J[6 * k + m];
                A[6 * r + k] = s;
            }
        if (!solve6(A, y)) return 0;
        double dq[6], n2 = 0.0;
        for (int m = 0; m < 6; m++) {
            dq[m] = 0.0;
            for (int r = 0; r < 6; r++) dq[m] += J[6 * r + m] * y[r];
            n2 += dq[m] * dq[m];
        }
        double scale = n2 > 0.25 ? 0.5 / sqrt(n2) : 1.0;
        for (int m = 0; m < 6; m++) q[m] = clampd(q[m] + scale * dq[m], c->lo[m], c->hi[m]);
    }
    return 0;
}

/* Size of jk_chain in bytes, so the Python side can check its layout matches. */
int jk_chain_size(void) { return (int)sizeof(jk_chain); }

/* Finite as the Python side counts it (kinematics._finite): values beyond 1e150 count as
 * infinite there, so they must not be solved here either. NaN fails the comparison. */
static int sane(double x) { return fabs(x) <= 1e150; }

/* jk_ik for the commonest request, straight from the caller's arrays: T the flange pose
 * (= joint-6 frame: the flange placement is identity), seed the reference joints (rad), no
 * tool offset. Checks what the Python side would (every value finite) and clamps the seed
 * into the limits; returns 0 for anything it does not solve (the Python path then answers,
 * with the proper error for bad input, without entering C again: jk_ik would only repeat this
 * same search). out: q (6) then the errors (2). */
int jk_ik_seeded(const jk_chain *c, const double *T, const double *seed, double pos_tol,
                 double rot_tol, double *out) {
    double ref[6];
    for (int k = 0; k < 16; k++)
        if (!sane(T[k])) return 0;
    for (int k = 0; k < 6; k++) {
        if (!sane(seed[k])) return 0;
        ref[k] = clampd(seed[k], c->lo[k], c->hi[k]);
    }
    return jk_ik(c, T, ref, NULL, pos_tol, rot_tol, out, out + 6);
}

/* The seeded fast path of the structures without a compiled closed form (MiniCobo, A12), as
 * Kinematics._ik_python's first attempt there: damped least squares from the seed (clamped
 * into the limits) for at most max_iter steps, then two Newton steps that settle the joints
 * (kept only if they succeed); answered only if no joint ended more than `radius` rad from
 * the seed — the seed's own branch. T: the flange pose (= joint-6 frame), no tool offset.
 * Returns the steps taken (>= 1) with out = q (6) then the errors (2), else 0. */
int jk_local_seeded(const jk_chain *c, const double *T, const double *seed, double pos_tol,
                    double rot_tol, int max_iter, double radius, double *out) {
    double ref[6], q[6], err[2];
    for (int k = 0; k < 16; k++)
        if (!sane(T[k])) return 0;
    for (int k = 0; k < 6; k++) {
        if (!sane(seed[k])) return 0;
        ref[k] = q[k] = clampd(seed[k], c->lo[k], c->hi[k]);
    }
    int steps = dls(c, T, pos_tol, rot_tol, max_iter, q, err);
    if (!steps) return 0;
    double q2[6], err2[2];
    memcpy(q2, q, sizeof q2);
    int settle = newton(c, T, NULL, pos_tol, rot_tol, 2, q2, err2);
    if (settle) {
        memcpy(q, q2, sizeof q);
        memcpy(err, err2, sizeof err);
    }
    for (int k = 0; k < 6; k++)
        if (fabs(q[k] - ref[k]) > radius) return 0;
    memcpy(out, q, sizeof q);
    out[6] = err[0];
    out[7] = err[1];
    return steps + settle;
}

/* The TCP at the joints q (rad), as a velocity jog measures it each cycle: its pose (pose: 4x4
 * row-major, m, base frame; = Kinematics.tcp_pose) and the smallest singular value of its
 * Jacobian (rows: the TCP point's velocity, m/s, and the angular velocity, rad/s, per rad/s of
 * each joint, base-frame axes; = Kinematics.jacobian, whose rows a rotation would not change
 * the singular values of). tool: the TCP in the model's joint-6 frame (4x4 row-major; the
 * flange frame when the flange placement is identity) or NULL for that frame. out: the pose
 * (16) then sigma (1). Returns 1, or 0 (nothing written) when a joint is not finite. */
int jk_tcp_sigma(const jk_chain *c, const double *q, const double *tool, double *out) {
    double R[6][9], p[6][3], R6[9], p6[3], Rt[9], pt[3], J[36];
    for (int k = 0; k < 6; k++)
        if (!sane(q[k])) return 0;
    forward(c, q, R, p, R6, p6);
    if (tool) {
        for (int r = 0; r < 3; r++) {
            pt[r] = p6[r] + R6[3 * r] * tool[3] + R6[3 * r + 1] * tool[7]
                    + R6[3 * r + 2] * tool[11];
            for (int k = 0; k < 3; k++)
                Rt[3 * r + k] = R6[3 * r] * tool[k] + R6[3 * r + 1] * tool[4 + k]
                                + R6[3 * r + 2] * tool[8 + k];
        }
    } else {
        memcpy(Rt, R6, sizeof Rt);
        memcpy(pt, p6, sizeof pt);
    }
    double *pose = out;
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) pose[4 * r + k] = Rt[3 * r + k];
        pose[4 * r + 3] = pt[r];
    }
    pose[12] = pose[13] = pose[14] = 0.0;
    pose[15] = 1.0;
    for (int k = 0; k < 6; k++) {       /* column k: z_k x (tcp - p_k); z_k */
        double z[3] = {R[k][2], R[k][5], R[k][8]};
        double d[3] = {pt[0] - p[k][0], pt[1] - p[k][1], pt[2] - p[k][2]};
        J[k] = z[1] * d[2] - z[2] * d[1];
        J[6 + k] = z[2] * d[0] - z[0] * d[2];
        J[12 + k] = z[0] * d[1] - z[1] * d[0];
        J[18 + k] = z[0];
        J[24 + k] = z[1];
        J[30 + k] = z[2];
    }
    out[16] = smallest_singular_value(J);
    return 1;
}
