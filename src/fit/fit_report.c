/* fit_report.c — the fit report as JSON (docs/fit.md lists every key). */
#include "fit/fit.h"
#include "core/outfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void write_json(const q2n_fit_report *r, const char *units, FILE *f);

/* JSON has no NaN or Infinity: a non-finite figure (none is expected; this is the last guard) is
 * written as null, so that every reader can still parse the report. */
void q2n_fit_report_write_json_file(const q2n_fit_report *r, const char *units, FILE *f)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    if (!m) { write_json(r, units, f); return; }
    write_json(r, units, m);
    fclose(m);
    for (size_t i = 0; i < len; i++) {
        /* printf's non-finite numbers: nan, -nan, inf, -inf (always after ": " or ", " here) */
        size_t k = i + (buf[i] == '-');
        int nan = !strncmp(buf + k, "nan", 3), inf = !strncmp(buf + k, "inf", 3);
        if ((nan || inf) && i > 0 && (buf[i - 1] == ' ' || buf[i - 1] == '[')) {
            fputs("null", f);
            i = k + 2;
            continue;
        }
        fputc(buf[i], f);
    }
    free(buf);
}

/* A figure for the report: -1 where it is not finite (a build that failed or folded to a cusp). */
static double fin(double x) { return isfinite(x) ? x : -1; }

static void write_json(const q2n_fit_report *r, const char *units, FILE *f)
{
    static const char *frame_names[] = {"own", "isotropic", "isotropic_charts", "isotropic_regions"};
    static const char *solvers[] = {"ceres_per_block", "ceres_sparse_normal_cholesky", "lapack_qr_per_block"};
    fprintf(f, "{\n  \"stage\": \"fit\",\n  \"faces\": %d,\n  \"edges\": %d,\n  \"interior_edges\": %d,\n",
            r->faces, r->edges, r->interior_edges);
    fprintf(f, "  \"mode\": \"%s\",\n  \"continuity\": \"G%d\",\n  \"tol\": %.17g,\n  \"tol_met\": %s,\n",
            r->exact ? "exact_bezier_conversion" : "least_squares_fit", r->continuity, r->tol,
            r->tol_met ? "true" : "false");
    if (units) fprintf(f, "  \"units\": \"%s\",\n", units);
    fprintf(f, "  \"tol_abs\": %.17g,\n  \"bbox_diag\": %.17g,\n  \"g1_tol_deg\": %.6g,\n  \"g2_tol_rel\": %.6g,\n",
            r->tol_abs, r->diag, r->g1_tol_deg, r->g2_tol_rel);
    fprintf(f, "  \"dev_met\": %s,\n  \"g1_met\": %s,\n  \"g2_met\": %s,\n  \"note\": \"%s\",\n",
            r->dev_met ? "true" : "false", r->g1_met ? "true" : "false", r->g2_met ? "true" : "false", r->note);
    fprintf(f, "  \"degree\": [5, 5],\n  \"rounds\": %d,\n", r->rounds);
    fprintf(f, "  \"g1_edges\": {\"exact\": %d, \"least_squares\": %d, \"within_rounding\": %d},\n", r->g1_exact_edges,
            r->g1_ls_edges, r->g1_rounding_edges);
    fprintf(f, "  \"spans_per_patch\": {\"min\": %d, \"median\": %d, \"max\": %d},\n  \"edge_spans_max\": %d,\n",
            r->spans_min, r->spans_median, r->spans_max, r->edge_spans_max);
    fprintf(f, "  \"control_points_per_patch\": {\"min\": %d, \"median\": %d, \"max\": %d, \"total\": %ld},\n",
            r->cp_min, r->cp_median, r->cp_max, r->cp_total);
    fprintf(f, "  \"file_bytes\": {\"step\": %ld, \"iges\": %ld},\n", r->step_bytes, r->iges_bytes);
    fprintf(f, "  \"samples\": %ld,\n  \"check_points\": %ld,\n", r->samples, r->checks);
    fprintf(f, "  \"max_dev_rel\": %.6g,\n  \"rms_dev_rel\": %.6g,\n  \"vertex_dev_max_rel\": %.6g,\n",
            r->max_dev_rel, r->rms_dev_rel, r->vertex_dev_max_rel);
    fprintf(f, "  \"g0_max_rel\": %.6g,\n  \"g1_max_deg\": %.6g,\n  \"g2_max_rel\": %.6g,\n",
            r->g0_max_rel, r->g1_max_deg, r->g2_max_rel);
    fprintf(f, "  \"rim\": {\"vertices\": %d, \"max_turn_deg\": %.6g, \"curvature_jump_rel\": %.6g, "
               "\"construction_max_turn_deg\": %.6g, \"construction_curvature_jump_rel\": %.6g},\n",
            r->rim_vertices, r->rim_max_deg, r->rim_curv_rel, r->rim_construction_deg, r->rim_construction_curv_rel);
    fprintf(f, "  \"construction\": {\"g1_max_deg\": %.6g, \"g2_max_rel\": %.6g, \"folded_faces\": %d, "
               "\"first_folded_face\": %d, \"vertices_moved_max_rel\": %.6g, \"flat_vertices\": %d, "
               "\"polynomial_edges\": %d, \"gluing_regions\": %d, \"smoothstep_regions\": %d, \"g2_folded_faces\": %d, \"paired_quads\": %d, \"triangles_left\": %d, \"filled_faces\": %d, "
               "\"fill_quads\": %d, \"frame\": {\"stretch\": %.6g, \"used\": \"%s\", \"ripple\": [%.6g, %.6g, %.6g, %.6g], "
               "\"energy\": [%.6g, %.6g, %.6g, %.6g]}},\n",
            r->g1_construction_deg, r->g2_construction_rel, r->folded_faces, r->folded_faces > 0 ? r->folded_face : -1,
            r->vertices_moved_rel, r->flat_vertices, r->polynomial_edges, r->gluing_regions, r->smoothstep_regions, r->g2_folded_faces, r->paired_quads, r->triangles_left,
            r->filled_faces, r->fill_quads, r->frame_stretch, frame_names[r->frame_used >= 0 && r->frame_used <= 3 ? r->frame_used : 0],
            fin(r->frame_ripple[0]), fin(r->frame_ripple[1]), fin(r->frame_ripple[2]), fin(r->frame_ripple[3]),
            fin(r->frame_energy[0]), fin(r->frame_energy[1]), fin(r->frame_energy[2]), fin(r->frame_energy[3]));
    fprintf(f, "  \"solver\": \"%s\",\n  \"threads\": %d,\n",
            solvers[r->solver >= 0 && r->solver <= 2 ? r->solver : 0], r->threads);
    fprintf(f, "  \"timings_s\": {\"sample\": %.6f, \"build\": %.6f, \"solve\": %.6f, \"measure\": %.6f, "
               "\"total\": %.6f}\n}\n", r->t_sample, r->t_build, r->t_solve, r->t_measure, r->t_total);
}

q2n_status q2n_fit_report_write_json(const q2n_fit_report *r, const char *path, q2n_error *err)
{
    q2n_outfile of;
    q2n_status st = q2n_outfile_open(&of, path, err);
    if (st) return st;
    q2n_fit_report_write_json_file(r, NULL, of.f);
    return q2n_outfile_commit(&of, err);
}
