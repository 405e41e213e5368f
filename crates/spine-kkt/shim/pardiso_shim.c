/* The library Ipopt opens as "libpardiso.so" (its SONAME): Pardiso's entry points, forwarded to
 * the Rust functions that spine-kkt registers right after loading it (src/abi.rs). Built by
 * build.rs; the Rust side writes it to a temporary file, loads it and deletes the file, and the
 * dynamic loader then hands this already loaded library to Ipopt's dlopen("libpardiso.so"). */

typedef void (*spine_init_fn)(void *pt, const int *mtype, const int *solver, int *iparm, double *dparm,
                              int *error);
typedef void (*spine_pardiso_fn)(void **pt, const int *maxfct, const int *mnum, const int *mtype,
                                 const int *phase, const int *n, const double *a, const int *ia,
                                 const int *ja, const int *perm, const int *nrhs, int *iparm,
                                 const int *msglvl, double *b, double *x, int *error, double *dparm);

static spine_init_fn spine_init = 0;
static spine_pardiso_fn spine_pardiso = 0;

/* Tells Ipopt's loader that this library has the Pardiso >= 4 calling convention. */
int pardiso_ipopt_newinterface = 1;

void spine_kkt_register(spine_init_fn init, spine_pardiso_fn pardiso) {
    spine_init = init;
    spine_pardiso = pardiso;
}

void pardisoinit(void *pt, const int *mtype, const int *solver, int *iparm, double *dparm, int *error) {
    if (!spine_init) { *error = -5; return; }
    spine_init(pt, mtype, solver, iparm, dparm, error);
}

void pardiso(void **pt, const int *maxfct, const int *mnum, const int *mtype, const int *phase,
             const int *n, const double *a, const int *ia, const int *ja, const int *perm,
             const int *nrhs, int *iparm, const int *msglvl, double *b, double *x, int *error,
             double *dparm) {
    if (!spine_pardiso) { *error = -5; return; }
    spine_pardiso(pt, maxfct, mnum, mtype, phase, n, a, ia, ja, perm, nrhs, iparm, msglvl, b, x, error, dparm);
}

void pardisoinit_(void *pt, const int *mtype, const int *solver, int *iparm, double *dparm, int *error) {
    pardisoinit(pt, mtype, solver, iparm, dparm, error);
}

void pardiso_(void **pt, const int *maxfct, const int *mnum, const int *mtype, const int *phase,
              const int *n, const double *a, const int *ia, const int *ja, const int *perm,
              const int *nrhs, int *iparm, const int *msglvl, double *b, double *x, int *error,
              double *dparm) {
    pardiso(pt, maxfct, mnum, mtype, phase, n, a, ia, ja, perm, nrhs, iparm, msglvl, b, x, error, dparm);
}
