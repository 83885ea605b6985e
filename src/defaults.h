/* ------------------------------------------------------------------ defaults */
RJDEF rj_link_def rj_default_link_def(void)
{
    rj_link_def d;
    memset(&d, 0, sizeof d);
    d.length = 1.0;
    d.elements = 10;
    d.E = 70e9;
    d.rho = 2710.0;
    d.section = RJ_SECTION_RECT;
    d.width = 0.05;
    d.height = 0.2;
    d.layers = 1;
    d.area = 0.0;
    d.inertia = 0.0;
    d.tip_mass = 0.0;
    d.tip_inertia = 0.0;
    d.root = RJ_ROOT_FREE;
    d.x = d.y = d.angle = 0.0;
    d.vx = d.vy = d.omega = 0.0;
    d.fidelity = RJ_LINK_FLEXIBLE;
    d.cookie = RJ__COOKIE_LINK;
    return d;
}
RJDEF rj_joint_def rj_default_joint_def(void)
{
    rj_joint_def d;
    memset(&d, 0, sizeof d);
    d.body1 = -1;
    d.node1 = -1;
    d.body2 = 0;
    d.ground_x = d.ground_y = d.ground_angle = 0.0;
    d.angle0 = RJ__PI;
    d.rate0 = 0.0;
    d.table_count = 0;
    d.spring_k = 0.0;
    d.spring_free_angle = RJ__PI;
    d.has_forward = 0;
    d.forward = 0.0;
    d.has_reverse = 0;
    d.reverse = 0.0;
    d.lock = 0;
    d.method = RJ_METHOD_ADAPTIVE;
    d.release = RJ_RELEASE_RC13;
    d.penalty_k = 0.0;
    d.restitution = 0.0;
    d.damping = 0.0;
    d.friction = 0.0;
    d.reference = RJ_REF_TANGENT;
    d.cookie = RJ__COOKIE_JOINT;
    return d;
}
RJDEF rj_solver_def rj_default_solver_def(void)
{
    rj_solver_def d;
    memset(&d, 0, sizeof d);
    d.dt = 0.0;
    d.allow_unstable = 0;
    d.energy_growth = 10.0;
    d.energy_every = 1;
    d.in_place = RJ_IN_PLACE_AUTO;
    d.cookie = RJ__COOKIE_SOLVER;
    return d;
}
RJDEF rj_load_def rj_default_load_def(void)
{
    rj_load_def d;
    memset(&d, 0, sizeof d);
    d.link = 0;
    d.node = -1;
    d.follower = 0;
    d.table_count = 0;
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

