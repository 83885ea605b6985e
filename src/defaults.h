/* ------------------------------------------------------------------ defaults */
/* Each definition's defaults are its rows' (fields.h); the cookie marks it as made here. */
RJDEF rj_link_def rj_default_link_def(void)
{
    rj_link_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_LINK);
    d.cookie = RJ__COOKIE_LINK;
    return d;
}
RJDEF rj_joint_def rj_default_joint_def(void)
{
    rj_joint_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_JOINT);
    d.cookie = RJ__COOKIE_JOINT;
    return d;
}
RJDEF rj_solver_def rj_default_solver_def(void)
{
    rj_solver_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_SOLVER);
    d.cookie = RJ__COOKIE_SOLVER;
    return d;
}
RJDEF rj_load_def rj_default_load_def(void)
{
    rj_load_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_LOAD);
    d.cookie = RJ__COOKIE_LOAD;
    return d;
}
RJDEF rj_scene_def rj_default_scene_def(void)
{
    rj_scene_def d;
    memset(&d, 0, sizeof d);
    d.links = NULL;
    d.link_count = 0;
    d.joints = NULL;
    d.joint_count = 0;
    d.solver = rj_default_solver_def();
    return d;
}
RJDEF rj_actuator_def rj_default_actuator_def(void)
{
    rj_actuator_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_ACTUATOR);
    d.cookie = RJ__COOKIE_ACTUATOR;
    return d;
}
RJDEF rj_coupling_def rj_default_coupling_def(void)
{
    rj_coupling_def d;
    rj__rows_default(&d, sizeof d, RJ__DEF_COUPLING);
    d.cookie = RJ__COOKIE_COUPLING;
    return d;
}
