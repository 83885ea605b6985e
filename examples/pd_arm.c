/* pd_arm - a controller swings a flexible arm to a target angle through the caller's joint
   torques (rj_state_joint_torques): an aluminium bar 1 m long, 20 x 10 mm, pinned at its
   root, under gravity; between steps a PD law with gravity feed-forward sets the shoulder's
   torque, tau = m g (L/2) cos(theta) + Kp (target - theta) - Kd omega, where theta is the
   arm's direction from root to tip and omega its angular momentum about the pin over its
   inertia. The root node alone has almost no inertia (the beam's mass sits along it), so
   feeding back the joint's own rate would make the gain Kd a damper on that node, far
   stiffer than the step allows; and the tip's rate carries the bending vibration, which a
   damper on it feeds (that loop went unstable in 0.3 s). The angular momentum changes only
   with the torques on the arm, not with its bending. Writes t, theta_deg, torque_Nm, tip_defl_m every 10 ms and the
   final error on standard error.
   usage: pd_arm [--target DEG] [--t-end S] [--kp N_m_per_rad] [--kd N_m_s_per_rad]
                 [--csv FILE]   (defaults 90 deg, 4 s, 2, 1, standard output) */
#define _POSIX_C_SOURCE 200809L
#define REVJOINT_IMPLEMENTATION
#include "../revjoint.h"
#include "scenes.h"
#include "cli.h"

#define G 9.81

static const char usage[] =
    "usage: pd_arm [--target DEG] [--t-end S] [--kp N_m_per_rad] [--kd N_m_s_per_rad] [--csv FILE]\n"
    "  a PD controller with gravity feed-forward swings a pinned flexible arm from horizontal\n"
    "  to the target angle through rj_state_joint_torques (defaults 90 deg, 4 s, Kp 2 N m/rad,\n"
    "  Kd 1 N m s/rad); CSV t,theta_deg (the arm's direction, root to tip),torque_Nm,\n"
    "  tip_defl_m every 10 ms\n";

/* The arm: one aluminium bar pinned at the origin, starting horizontal. */
static rj_result arm_build(rj_model **m, rj_error *err)
{
    rj_link_def l = rj_default_link_def();
    rj_joint_def j = rj_default_joint_def();
    rj_scene_def sc = rj_default_scene_def();
    l.length = 1.0;
    l.elements = 10;
    l.E = 70e9;
    l.rho = 2700;
    l.section = RJ_SECTION_RECT;
    l.width = 0.02;
    l.height = 0.01;
    j.body1 = -1;
    j.body2 = 0;
    j.angle0 = 0;
    sc.links = &l;
    sc.link_count = 1;
    sc.joints = &j;
    sc.joint_count = 1;
    sc.solver.gravity[1] = -G;
    return rj_model_create(&sc, m, err, NULL);
}

/* The arm's direction from root to tip (rad), and its mean rate: angular momentum over
   inertia about the pin (rad/s), which bending does not change, so a damper on it cannot
   feed the arm's vibration. */
static void arm_direction(const rj_model *m, const rj_state *s, double *theta, double *rate)
{
    const int n = rj_link_node_count(m, 0);
    double p0[2], p1[2], momentum = 0, inertia = 0;
    int k;
    rj_node_position(m, s, 0, 0, p0);
    rj_node_position(m, s, 0, n - 1, p1);
    *theta = atan2(p1[1] - p0[1], p1[0] - p0[0]);
    for (k = 0; k < n; k++) {
        double mk, jk, xk[2], vk[2];
        rj_node_mass(m, 0, k, &mk, &jk);
        rj_node_position(m, s, 0, k, xk);
        rj_node_velocity(m, s, 0, k, vk);
        xk[0] -= p0[0];
        xk[1] -= p0[1];
        momentum += mk * (xk[0] * vk[1] - xk[1] * vk[0]) + jk * rj_node_rate(m, s, 0, k);
        inertia += mk * (xk[0] * xk[0] + xk[1] * xk[1]) + jk;
    }
    *rate = momentum / inertia;
}

/* The controller's torque for the state now. */
static double pd_torque(const rj_model *m, const rj_state *s, double target, double kp, double kd)
{
    double moment = 0, theta, rate;
    const int n = rj_link_node_count(m, 0);
    int k;
    /* gravity's moment about the pin for the arm held straight: sum m_k x_k */
    for (k = 0; k < n; k++) {
        double mk, jk, xk[2], x0[2];
        rj_node_mass(m, 0, k, &mk, &jk);
        rj_node_position(m, s, 0, k, xk);
        rj_node_position(m, s, 0, 0, x0);
        moment += mk * hypot(xk[0] - x0[0], xk[1] - x0[1]);
    }
    arm_direction(m, s, &theta, &rate);
    return moment * G * cos(theta) + kp * (target - theta) - kd * rate;
}

int main(int argc, char **argv)
{
    double target = rj_rad(90), t_end = 4, kp = 2, kd = 1, next = 0;
    const char *csv = NULL, *a;
    cli c;
    cli_out out;
    rj_model *m;
    rj_state *s;
    rj_error err;
    double *torque;
    c.argc = argc;
    c.argv = argv;
    c.i = 0;
    c.usage = usage;
    while ((a = cli_next(&c)) != NULL) {
        if (!strcmp(a, "--target")) target = rj_rad(cli_num(&c, a, -360, 360));
        else if (!strcmp(a, "--t-end")) t_end = cli_num(&c, a, 0, 1e4);
        else if (!strcmp(a, "--kp")) kp = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--kd")) kd = cli_num(&c, a, 0, 1e6);
        else if (!strcmp(a, "--csv")) csv = cli_str(&c, a);
        else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else cli_die(&c, "unknown option '%s'%s", a, "");
    }
    if (arm_build(&m, &err) != RJ_OK) {
        fprintf(stderr, "pd_arm: %s\n", err.msg);
        return 1;
    }
    if (rj_state_create(m, &s, NULL) != RJ_OK || cli_open(&out, "pd_arm", csv) != 0) return 1;
    torque = rj_state_joint_torques(m, s);
    cli_put(&out, fputs("t,theta_deg,torque_Nm,tip_defl_m\n", out.f));
    /* the controller acts between steps: a new torque from the state each step */
    while (rj_state_time(s) < t_end) {
        torque[0] = pd_torque(m, s, target, kp, kd);
        if (rj_state_time(s) >= next - 1e-12) {
            double theta, rate;
            arm_direction(m, s, &theta, &rate);
            cli_put(&out, fprintf(out.f, "%.6f,%.8g,%.8g,%.8g\n", rj_state_time(s), rj_deg(theta),
                                  torque[0], scene_tip_defl_tangent(m, s, 0)));
            next += 0.01;
        }
        if (rj_step(m, s) != RJ_OK) {
            fprintf(stderr, "pd_arm: %s\n", rj_state_error(s));
            return 1;
        }
    }
    if (cli_close(&out, "pd_arm") != 0) return 1;
    {
        rj_energy e;
        double theta, rate;
        rj_state_energy(m, s, &e);
        arm_direction(m, s, &theta, &rate);
        fprintf(stderr, "pd_arm: the arm at %.4f deg at t = %.3f s (target %.4f deg); the controller "
                        "did %.6g J of work, energy balance %.3g J\n",
                rj_deg(theta), rj_state_time(s), rj_deg(target), e.work_applied, e.balance);
    }
    rj_state_destroy(s, NULL);
    rj_model_destroy(m, NULL);
    return 0;
}
