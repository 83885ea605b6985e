#define REVJOINT_IMPLEMENTATION
#include "revjoint.h"
#include <stdio.h>

int main(void) {
    rj_link_def links[2] = { rj_default_link_def(), rj_default_link_def() };
    rj_joint_def joints[2] = { rj_default_joint_def(), rj_default_joint_def() };
    rj_scene_def scene = rj_default_scene_def();
    rj_model *m; rj_state *s; rj_error err;
    links[0].height = links[1].height = 0.01;                 /* 1 m aluminium strips, 10 elements */
    joints[0].body1 = -1; joints[0].body2 = 0;                /* link 0 pinned to ground */
    joints[0].angle0 = 0; joints[0].spring_k = 20; joints[0].spring_free_angle = rj_rad(90);
    joints[1].body1 = 0;  joints[1].body2 = 1;                /* link 1 hangs from link 0's tip */
    joints[1].has_reverse = 1; joints[1].reverse = rj_rad(150); joints[1].lock = 1;
    joints[1].spring_k = 5; joints[1].spring_free_angle = rj_rad(90);
    scene.links = links; scene.link_count = 2; scene.joints = joints; scene.joint_count = 2;
    if (rj_model_create(&scene, &m, &err, NULL) != RJ_OK) { puts(err.msg); return 1; }
    rj_state_create(m, &s, NULL);
    while (rj_state_time(s) < 0.5 && rj_step(m, s) == RJ_OK) {}
    printf("t %.3f s: joint 1 at %.2f deg, flag %d\n", rj_state_time(s),
           rj_deg(rj_joint_theta(m, s, 1)), rj_joint_flag(m, s, 1));
    rj_state_destroy(s, NULL); rj_model_destroy(m, NULL);
    if (fflush(stdout) != 0 || ferror(stdout)) { perror("quickstart: stdout"); return 1; }
    return 0;
}
