/* rjt_loads.h - what the load tests share: the complete elliptic integral of the pendulum's
   exact period, a link's mass, first moment and inertia as the model lumps them, and the
   pendulum's swing as rj_run samples it.
   Include after revjoint.h and <math.h>. */
#ifndef RJT_LOADS_H
#define RJT_LOADS_H

/* K(k), the complete elliptic integral of the first kind, by the arithmetic-geometric
   mean: K = pi / (2 AGM(1, sqrt(1 - k^2))). */
static double elliptic_k(double k)
{
    double a = 1.0, b = sqrt(1.0 - k * k);
    int i;
    for (i = 0; i < 40; i++) {
        const double an = 0.5 * (a + b);
        b = sqrt(a * b);
        a = an;
    }
    return 3.14159265358979323846 / (2.0 * a);
}

/* Mass, first moment and inertia about node 0 of a link as the model lumps it. */
static void lumped_body(const rj_model *m, const rj_state *s, int link, double *mass, double *moment,
                        double *inertia)
{
    const int n = rj_link_node_count(m, link);
    double x0[2];
    int k;
    *mass = *moment = *inertia = 0;
    rj_node_position(m, s, link, 0, x0);
    for (k = 0; k < n; k++) {
        double mk, jk, xk[2];
        rj_node_mass(m, link, k, &mk, &jk);
        rj_node_position(m, s, link, k, xk);
        {
            const double r = hypot(xk[0] - x0[0], xk[1] - x0[1]);
            *mass += mk;
            *moment += mk * r;
            *inertia += mk * r * r + jk;
        }
    }
}

/* A pendulum's angle from straight down (where gravity or the force points), the times
   it passes there going one way (linear interpolation between steps), and its tip (node
   tip_node of link 0) one sample back and now. */
typedef struct swing {
    double phi_prev, t_prev;
    double crossing[8];
    int crossings;
    int tip_node;
    double tip_before[2], tip_now[2]; /* the tip one step back and now */
} swing;

static int swing_sample(const rj_model *m, const rj_state *s, void *user)
{
    swing *w = (swing *)user;
    const double t = rj_state_time(s);
    const double phi = rj_joint_theta_running(m, s, 0) + 0.5 * 3.14159265358979323846;
    if (t > 0 && w->phi_prev > 0 && phi <= 0 && w->crossings < 8)
        w->crossing[w->crossings++] = w->t_prev + (t - w->t_prev) * w->phi_prev / (w->phi_prev - phi);
    w->phi_prev = phi;
    w->t_prev = t;
    w->tip_before[0] = w->tip_now[0];
    w->tip_before[1] = w->tip_now[1];
    rj_node_position(m, s, 0, w->tip_node, w->tip_now);
    return 0;
}

#endif
