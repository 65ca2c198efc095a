/* report.h - reports shared by the commands: metrics as JSON fields and as
 * text (largesteps metrics, largesteps fit's metrics.json and summary). */
#ifndef LS_REPORT_H
#define LS_REPORT_H

#include <stdio.h>
#include <largesteps.h>

/* A JSON string literal with escapes. */
void ls_report_json_string(FILE *f, const char *s);

/* A JSON number: "%.9g", or null when not finite (JSON has no inf or nan). */
void ls_report_json_number(FILE *f, double v);

/* The fields (no braces) of a distance report (numbers that are not finite
 * are written as null and listed, with "inf", "-inf" or "nan", in a last
 * "not_finite" object): symmetric values, then
 * "a_to_b" and "b_to_a" objects; each line indented by two spaces and ended
 * with ",\n". */
void ls_report_json_distance(FILE *f, const ls_distance_report *d);

/* "name": {tangling metrics}, then ",\n" when comma, else "\n". */
void ls_report_json_tangle(FILE *f, const char *name, const ls_tangle_report *t, int comma);

/* The symmetric distances and tangling of a result as text lines. */
void ls_report_text_distance(FILE *f, const ls_distance_report *d);
void ls_report_text_tangle(FILE *f, const char *name, const ls_tangle_report *t);

/* The remaining time of a fit that remeshes. A remesh multiplies the
 * vertices (by about 1 / remesh_h^2), so the iterations after it are slower
 * and the remesh itself takes time: the estimate runs from the time per
 * iteration of the current mesh (the iterations since the last remesh), and
 * each remesh still scheduled costs what the last one did (times the
 * growth) and multiplies the time per iteration by the growth, measured at
 * the last remesh (time per iteration after / before), 1 / remesh_h before
 * any was measured (the renders cost per pixel, so the time grows more
 * slowly than the vertex count). */
typedef struct ls_report_eta {
    const uint32_t *remesh_at; /* the schedule: remeshes before these iterations */
    uint32_t remesh_count;
    double guess;              /* growth before one was measured */
    uint32_t seg_it;           /* first iteration on the current mesh */
    double seg_ms;             /* elapsed time when it started */
    double prev_rate;          /* ms per iteration before the last remesh (0: no remesh yet) */
    double remesh_ms;          /* the last remesh's time (0: none yet) */
} ls_report_eta;

void ls_report_eta_init(ls_report_eta *e, const uint32_t *remesh_at, uint32_t remesh_count, double remesh_h);

/* A remesh before iteration `it`, from start_ms to end_ms (elapsed time). */
void ls_report_eta_remesh(ls_report_eta *e, uint32_t it, double start_ms, double end_ms);

/* Milliseconds left after `done` of `total` iterations, elapsed_ms so far. */
double ls_report_eta_ms(const ls_report_eta *e, uint32_t done, uint32_t total, double elapsed_ms);

/* The views a contact sheet shows: all of them up to LS_REPORT_SHEET_VIEWS,
 * else that many spread over the pool; ls_report_sheet_view gives the view
 * index of column `column`. */
#define LS_REPORT_SHEET_VIEWS 16u
uint32_t ls_report_sheet_views(uint32_t views);
uint32_t ls_report_sheet_view(uint32_t column, uint32_t views);

/* The finishing of `largesteps fit`'s contact sheet (3 rows of
 * ls_report_sheet_views(views) tiles: target, initial, result): each tile
 * labelled "<row> <view>", then the sheet put over a grey checkerboard
 * (ls_contact_backdrop: 8-pixel squares of 0.35 and 0.55) so that a mask
 * fit's white silhouettes show. */
ls_status ls_report_fit_sheet(ls_contact *sheet, uint32_t views);

#endif /* LS_REPORT_H */
