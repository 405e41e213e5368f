/* The calls of MUMPS's C interface (dmumps_c.h, MUMPS 5.5, sequential) that spine-mumps needs:
 * analysis, factorisation, inertia and solve of a symmetric indefinite matrix given by its upper
 * triangle in 1-based coordinates, with the controls Ipopt's MUMPS interface sets by default
 * (ICNTL(6) = 7, ICNTL(7) = 7, ICNTL(8) = 77, ICNTL(10) = 0, ICNTL(13) = 1, ICNTL(14) = 1000,
 * CNTL(1) = 1e-6). The arrays stay owned by the caller and must outlive the handle. */
#include <stdlib.h>
#include <dmumps_c.h>

#define USE_COMM_WORLD -987654

typedef struct {
    DMUMPS_STRUC_C id;
} spine_mumps;

/* Initialises MUMPS and runs the analysis (JOB = 1). Returns NULL with *info = INFOG(1) (or
 * -1000 when out of memory) on failure. */
spine_mumps *spine_mumps_analyse(int n, long long nnz, int *irn, int *jcn, double *a, int *info) {
    spine_mumps *m = calloc(1, sizeof *m);
    if (m == NULL) {
        *info = -1000;
        return NULL;
    }
    m->id.job = -1;
    m->id.par = 1;
    m->id.sym = 2;
    m->id.comm_fortran = USE_COMM_WORLD;
    dmumps_c(&m->id);
    if (m->id.infog[0] < 0) {
        *info = m->id.infog[0];
        free(m);
        return NULL;
    }
    m->id.icntl[0] = -1;
    m->id.icntl[1] = -1;
    m->id.icntl[2] = -1;
    m->id.icntl[3] = 0;
    m->id.n = n;
    m->id.nnz = nnz;
    m->id.irn = irn;
    m->id.jcn = jcn;
    m->id.a = a;
    m->id.icntl[5] = 7;
    m->id.icntl[6] = 7;
    m->id.icntl[7] = 77;
    m->id.icntl[9] = 0;
    m->id.icntl[12] = 1;
    m->id.icntl[13] = 1000;
    m->id.cntl[0] = 1e-6;
    m->id.job = 1;
    dmumps_c(&m->id);
    *info = m->id.infog[0];
    return m;
}

/* Numerical factorisation (JOB = 2) of the current values; returns INFOG(1). */
int spine_mumps_factor(spine_mumps *m) {
    m->id.job = 2;
    dmumps_c(&m->id);
    return m->id.infog[0];
}

/* The number of negative pivots of the last factorisation, INFOG(12). */
int spine_mumps_negative(const spine_mumps *m) {
    return m->id.infog[11];
}

/* Overwrites rhs (length n) with the solution (JOB = 3); returns INFOG(1). */
int spine_mumps_solve(spine_mumps *m, double *rhs) {
    m->id.rhs = rhs;
    m->id.nrhs = 1;
    m->id.lrhs = m->id.n;
    m->id.job = 3;
    dmumps_c(&m->id);
    return m->id.infog[0];
}

/* Frees MUMPS's storage (JOB = -2) and the handle. */
void spine_mumps_free(spine_mumps *m) {
    if (m == NULL) {
        return;
    }
    m->id.job = -2;
    dmumps_c(&m->id);
    free(m);
}
