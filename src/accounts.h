/* ------------------------------------------------------------------ energy accounts */
/* The energy accounts, one row each: its column in rj run, the frame scalar that holds
   it, where it stands in the balance (an energy in the total; a loss added to it; work
   done on the model taken from it), and its field in rj_energy. rj_state_energy, the
   first step's zeroing, the checkpoints' check and rj run's columns read this table; the
   step accumulates each account where its physics is (rj__sums). An account is a row
   here, a frame scalar (RJ__FS_*), a field of rj_energy and its physics. */
enum rj__account_kind { RJ__ACC_ENERGY = 0, RJ__ACC_LOSS, RJ__ACC_WORK };
/* What a model needs for an account to move: nothing (every model), actuators, links with
   structural damping, links with yielding layers. */
enum rj__account_need {
    RJ__NEED_NONE = 0,
    RJ__NEED_ACTUATORS,
    RJ__NEED_STRUCTURAL,
    RJ__NEED_PLASTIC
};
typedef struct rj__account {
    char column[16]; /* rj run's column name */
    int slot;        /* RJ__FS_* */
    int kind;        /* rj__account_kind */
    size_t field;    /* offsetof(rj_energy, ...) */
    int need;        /* rj__account_need */
} rj__account;
#define RJ__ACCOUNT_COUNT 11
static const rj__account rj__accounts[RJ__ACCOUNT_COUNT] = {
    { "E_kin", RJ__FS_KE, RJ__ACC_ENERGY, offsetof(rj_energy, kinetic), RJ__NEED_NONE },
    { "E_strain", RJ__FS_STRAIN, RJ__ACC_ENERGY, offsetof(rj_energy, strain), RJ__NEED_NONE },
    { "E_spring", RJ__FS_SPRING, RJ__ACC_ENERGY, offsetof(rj_energy, spring), RJ__NEED_NONE },
    { "E_gravity", RJ__FS_GRAV, RJ__ACC_ENERGY, offsetof(rj_energy, gravity), RJ__NEED_NONE },
    { "W_applied", RJ__FS_WORK, RJ__ACC_WORK, offsetof(rj_energy, work_applied), RJ__NEED_NONE },
    { "W_drive", RJ__FS_DRIVE, RJ__ACC_WORK, offsetof(rj_energy, work_drive), RJ__NEED_ACTUATORS },
    { "W_damping", RJ__FS_LDAMP, RJ__ACC_LOSS, offsetof(rj_energy, lost_damping), RJ__NEED_NONE },
    { "W_friction", RJ__FS_LFRIC, RJ__ACC_LOSS, offsetof(rj_energy, lost_friction), RJ__NEED_NONE },
    { "W_limit", RJ__FS_LLIM, RJ__ACC_LOSS, offsetof(rj_energy, lost_limit), RJ__NEED_NONE },
    { "W_structural", RJ__FS_LSTRUCT, RJ__ACC_LOSS, offsetof(rj_energy, lost_structural),
      RJ__NEED_STRUCTURAL },
    { "W_plastic", RJ__FS_LPLAST, RJ__ACC_LOSS, offsetof(rj_energy, lost_plastic),
      RJ__NEED_PLASTIC },
};

RJDEF int rj_energy_account_count(void)
{
    return RJ__ACCOUNT_COUNT;
}

RJDEF const char *rj_energy_account_name(int k)
{
    RJ_ASSERT(k >= 0 && k < RJ__ACCOUNT_COUNT);
    return rj__accounts[k].column;
}

RJDEF int rj_energy_account_in(const rj_model *m, int k)
{
    RJ_ASSERT(m && k >= 0 && k < RJ__ACCOUNT_COUNT);
    switch (rj__accounts[k].need) {
    case RJ__NEED_ACTUATORS:
        return m->nact > 0;
    case RJ__NEED_STRUCTURAL:
        return m->nstruct > 0;
    case RJ__NEED_PLASTIC:
        return m->nplastic > 0;
    default:
        return 1;
    }
}

RJDEF int rj_model_actuator_count(const rj_model *m)
{
    return m->nact;
}

RJDEF double rj_energy_account(const rj_energy *e, int k)
{
    RJ_ASSERT(e && k >= 0 && k < RJ__ACCOUNT_COUNT);
    return *(const double *) (const void *) ((const char *) e + rj__accounts[k].field);
}

/* The total and the balance from a frame's scalars: the energies summed in the table's
   order, then the losses added, the work taken away and the initial energy last. *e
   receives each account (NULL: the sums alone, as the checkpoints' check wants). */
static double rj__accounts_read(const double *scalars, rj_energy *e, double *total)
{
    double sum = 0, balance;
    int k;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++) {
        const double v = scalars[rj__accounts[k].slot];
        if (e)
            *(double *) (void *) ((char *) e + rj__accounts[k].field) = v;
        if (rj__accounts[k].kind == RJ__ACC_ENERGY)
            sum = k == 0 ? v : sum + v;
    }
    balance = sum;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind == RJ__ACC_LOSS)
            balance += scalars[rj__accounts[k].slot];
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind == RJ__ACC_WORK)
            balance -= scalars[rj__accounts[k].slot];
    *total = sum;
    return balance - scalars[RJ__FS_E0];
}

/* A first step's accounts: every loss and work from zero. */
static void rj__accounts_zero(double *scalars)
{
    int k;
    for (k = 0; k < RJ__ACCOUNT_COUNT; k++)
        if (rj__accounts[k].kind != RJ__ACC_ENERGY)
            scalars[rj__accounts[k].slot] = 0;
}
