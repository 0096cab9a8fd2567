/* obj_writer.c — writes a q2n_mesh as OBJ (`v` and `f` records only, coordinates as %.17g so
 * that reading the file back gives the same doubles).  Atomic and durable (core/outfile.h): a
 * temporary in the same directory, synced, renamed over PATH, so a reader never sees a
 * half-written file.  Numbers are formatted in the "C" locale. */
#include "mesh/mesh.h"

#include "core/outfile.h"

#include <locale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int write_records(const q2n_mesh *m, FILE *fp)
{
    for (int v = 0; v < m->nv; v++) {
        const double *p = q2n_mesh_vpos(m, v);
        if (fprintf(fp, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]) < 0) return -1;
    }
    for (int f = 0; f < m->nf; f++) {
        if (fputc('f', fp) == EOF) return -1;
        for (int i = m->face_start[f]; i < m->face_start[f + 1]; i++)
            if (fprintf(fp, " %d", m->face_vert[i] + 1) < 0) return -1;
        if (fputc('\n', fp) == EOF) return -1;
    }
    return 0;
}

q2n_status q2n_mesh_write_obj(const q2n_mesh *m, const char *path, q2n_error *err)
{
    if (!m || !path) return q2n_error_set(err, Q2N_ERR_ARG, "write_obj: NULL argument");
    q2n_outfile o;
    q2n_status st = q2n_outfile_open(&o, path, err);
    if (st) return st;
    locale_t cloc = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0), old = (locale_t)0;
    if (cloc) old = uselocale(cloc);
    int bad = write_records(m, o.f);
    if (cloc) {
        uselocale(old);
        freelocale(cloc);
    }
    if (bad) {
        q2n_outfile_abort(&o);
        return q2n_error_set(err, Q2N_ERR_IO, "%s: write failed", path);
    }
    return q2n_outfile_commit(&o, err);
}
