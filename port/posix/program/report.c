/* report.c - metrics reports shared by the commands (see report.h). */
#include <stdio.h>
#include <stdint.h>
#include "report.h"

void ls_report_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != 0; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c < 0x20) fprintf(f, "\\u%04x", (unsigned)c);
        else fputc(c, f);
    }
    fputc('"', f);
}

/* Non-finite numbers are not JSON: each is written as null, and its name and
 * value are collected for a "not_finite" object that says why. */
static char why[1024];
static size_t why_len;

static void why_reset(void)
{
    why[0] = 0;
    why_len = 0;
}

static void num(FILE *f, const char *prefix, const char *name, double v)
{
    int n;
    if (v == v && v - v == 0) {
        fprintf(f, "%.9g", v);
        return;
    }
    fputs("null", f);
    n = snprintf(why + why_len, sizeof why - why_len, "%s\"%s%s%s\": \"%s\"", why_len > 0 ? ", " : "",
                 prefix != NULL ? prefix : "", prefix != NULL ? "." : "", name,
                 v != v ? "nan" : v > 0 ? "inf" : "-inf");
    if (n > 0 && (size_t)n < sizeof why - why_len) why_len += (size_t)n;
}

void ls_report_json_number(FILE *f, double v)
{
    if (v == v && v - v == 0) fprintf(f, "%.9g", v);
    else fputs("null", f);
}

static void json_stats(FILE *f, const char *way, const char *name, const ls_dist_stats *s, int comma)
{
    char prefix[64];
    snprintf(prefix, sizeof prefix, "%s.%s", way, name);
    fprintf(f, "\"%s\": {\"max\": ", name);
    num(f, prefix, "max", (double)s->max);
    fprintf(f, ", \"mean\": ");
    num(f, prefix, "mean", (double)s->mean);
    fprintf(f, ", \"rms\": ");
    num(f, prefix, "rms", (double)s->rms);
    fprintf(f, ", \"count\": %u, \"argmax\": %lld}%s", (unsigned)s->count,
            s->argmax == UINT32_MAX ? -1LL : (long long)s->argmax, comma ? ", " : "");
}

static void json_one_way(FILE *f, const char *name, const ls_dist_one_way *w)
{
    fprintf(f, "  \"%s\": {", name);
    json_stats(f, name, "vertex", &w->vertex, 1);
    json_stats(f, name, "face", &w->face, 1);
    json_stats(f, name, "normal_deg", &w->normal, 0);
    fprintf(f, "},\n");
}

/* "name": value, (value null when not finite) */
static void field(FILE *f, const char *prefix, const char *name, double v, const char *sep)
{
    fprintf(f, "\"%s\": ", name);
    num(f, prefix, name, v);
    fputs(sep, f);
}

void ls_report_json_distance(FILE *f, const ls_distance_report *d)
{
    why_reset();
    fputs("  ", f);
    field(f, NULL, "diag_b", (double)d->diag, ",\n  ");
    field(f, NULL, "vertex_hausdorff", (double)d->vertex_hausdorff, ", ");
    field(f, NULL, "vertex_hausdorff_rel", (double)d->vertex_hausdorff_rel, ",\n  ");
    field(f, NULL, "hausdorff", (double)d->hausdorff, ", ");
    field(f, NULL, "hausdorff_rel", (double)d->hausdorff_rel, ",\n  ");
    field(f, NULL, "mean", (double)d->mean, ", ");
    field(f, NULL, "mean_rel", (double)d->mean_rel, ",\n  ");
    field(f, NULL, "rms", (double)d->rms, ", ");
    field(f, NULL, "rms_rel", (double)d->rms_rel, ",\n");
    json_one_way(f, "a_to_b", &d->ab);
    json_one_way(f, "b_to_a", &d->ba);
    /* why some numbers are null: the values that are not finite (coordinates
     * near the range of ls_real overflow in the distances) */
    if (why_len > 0) fprintf(f, "  \"not_finite\": {%s},\n", why);
}

void ls_report_json_tangle(FILE *f, const char *name, const ls_tangle_report *t, int comma)
{
    why_reset();
    fprintf(f, "  \"%s\": {\"intersecting_pairs\": %u, \"intersecting_faces\": %u, \"degenerate_faces\": %u, ", name,
            (unsigned)t->intersecting_pairs, (unsigned)t->intersecting_faces, (unsigned)t->degenerate_faces);
    if (t->has_reference)
        fprintf(f, "\"inverted_faces\": %u, ", (unsigned)t->inverted_faces);
    else
        fprintf(f, "\"inverted_faces\": null, ");
    fprintf(f, "\"angle_deg\": {");
    field(f, "angle_deg", "min", (double)t->angle_min, ", ");
    field(f, "angle_deg", "p1", (double)t->angle_p1, ", ");
    field(f, "angle_deg", "p5", (double)t->angle_p5, ", ");
    field(f, "angle_deg", "p50", (double)t->angle_p50, ", ");
    field(f, "angle_deg", "max", (double)t->angle_max, "}, ");
    fprintf(f, "\"quality\": {");
    field(f, "quality", "min", (double)t->quality_min, ", ");
    field(f, "quality", "p1", (double)t->quality_p1, ", ");
    field(f, "quality", "p5", (double)t->quality_p5, ", ");
    field(f, "quality", "p50", (double)t->quality_p50, ", ");
    field(f, "quality", "mean", (double)t->quality_mean, "}");
    if (why_len > 0) fprintf(f, ", \"not_finite\": {%s}", why);
    fprintf(f, "}%s\n", comma ? "," : "");
}

void ls_report_text_distance(FILE *f, const ls_distance_report *d)
{
    fprintf(f, "symmetric            absolute      / diag(target)\n");
    fprintf(f, "  H vertices         %-13.6g %.6g   (= igl::hausdorff)\n", (double)d->vertex_hausdorff,
            (double)d->vertex_hausdorff_rel);
    fprintf(f, "  H (all samples)    %-13.6g %.6g\n", (double)d->hausdorff, (double)d->hausdorff_rel);
    fprintf(f, "  mean               %-13.6g %.6g\n", (double)d->mean, (double)d->mean_rel);
    fprintf(f, "  rms                %-13.6g %.6g\n", (double)d->rms, (double)d->rms_rel);
}

void ls_report_text_tangle(FILE *f, const char *name, const ls_tangle_report *t)
{
    fprintf(f, "%s self-intersecting pairs %u (%u faces)", name, (unsigned)t->intersecting_pairs,
            (unsigned)t->intersecting_faces);
    if (t->intersecting_pairs > 0) fprintf(f, ", first %u-%u", (unsigned)t->first_pair[0], (unsigned)t->first_pair[1]);
    fprintf(f, "; degenerate faces %u", (unsigned)t->degenerate_faces);
    if (t->has_reference) fprintf(f, "; inverted %u", (unsigned)t->inverted_faces);
    fprintf(f, "\n%s angles    min %.3f p1 %.3f p5 %.3f p50 %.3f max %.3f deg\n", name, (double)t->angle_min,
            (double)t->angle_p1, (double)t->angle_p5, (double)t->angle_p50, (double)t->angle_max);
    fprintf(f, "%s quality   min %.4f p1 %.4f p5 %.4f p50 %.4f mean %.4f (2 r / R)\n", name, (double)t->quality_min,
            (double)t->quality_p1, (double)t->quality_p5, (double)t->quality_p50, (double)t->quality_mean);
}

uint32_t ls_report_sheet_views(uint32_t views)
{
    return views < LS_REPORT_SHEET_VIEWS ? views : LS_REPORT_SHEET_VIEWS;
}

uint32_t ls_report_sheet_view(uint32_t column, uint32_t views)
{
    return (uint32_t)((uint64_t)column * views / ls_report_sheet_views(views));
}

ls_status ls_report_fit_sheet(ls_contact *sheet, uint32_t views)
{
    static const char *const rows[3] = {"target", "initial", "result"};
    const uint32_t shown = ls_report_sheet_views(views);
    char text[32];
    uint32_t r, v;
    ls_status st = LS_OK;
    for (r = 0; r < 3u && st == LS_OK; r++)
        for (v = 0; v < shown && st == LS_OK; v++) {
            snprintf(text, sizeof text, "%s %u", rows[r], (unsigned)ls_report_sheet_view(v, views));
            st = ls_contact_label(sheet, r * shown + v, text);
        }
    return st == LS_OK ? ls_contact_backdrop(sheet, 8, 0.35f, 0.55f) : st;
}

void ls_report_eta_init(ls_report_eta *e, const uint32_t *remesh_at, uint32_t remesh_count, double remesh_h)
{
    e->remesh_at = remesh_at;
    e->remesh_count = remesh_count;
    e->guess = remesh_h > 0 && remesh_h < 1 ? 1.0 / remesh_h : 1.0;
    e->seg_it = 0;
    e->seg_ms = 0;
    e->prev_rate = 0;
    e->remesh_ms = 0;
}

void ls_report_eta_remesh(ls_report_eta *e, uint32_t it, double start_ms, double end_ms)
{
    if (it > e->seg_it) e->prev_rate = (start_ms - e->seg_ms) / (double)(it - e->seg_it);
    e->seg_it = it;
    e->seg_ms = end_ms;
    e->remesh_ms = end_ms - start_ms;
}

double ls_report_eta_ms(const ls_report_eta *e, uint32_t done, uint32_t total, double elapsed_ms)
{
    double rate, growth = e->guess, eta = 0;
    uint32_t pos = done, i;
    if (done >= total) return 0;
    if (done > e->seg_it) rate = (elapsed_ms - e->seg_ms) / (double)(done - e->seg_it);
    else if (e->prev_rate > 0) rate = e->prev_rate * growth;
    else return 0;
    /* measured once a few iterations ran on the new mesh */
    if (e->prev_rate > 0 && done >= e->seg_it + 3u) growth = rate / e->prev_rate;
    if (growth < 1) growth = 1;
    for (i = 0; i < e->remesh_count; i++) {
        uint32_t at = e->remesh_at[i];
        if (at < done || at >= total) continue;
        eta += (double)(at - pos) * rate + e->remesh_ms * growth;
        rate *= growth;
        pos = at;
    }
    return eta + (double)(total - pos) * rate;
}
