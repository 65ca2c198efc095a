/* report.h - reports shared by the commands: metrics as JSON fields and as
 * text (largesteps metrics, largesteps fit's metrics.json and summary). */
#ifndef LS_REPORT_H
#define LS_REPORT_H

#include <stdio.h>
#include <largesteps.h>

/* A JSON string literal with escapes. */
void ls_report_json_string(FILE *f, const char *s);

/* The fields (no braces) of a distance report: symmetric values, then
 * "a_to_b" and "b_to_a" objects; each line indented by two spaces and ended
 * with ",\n". */
void ls_report_json_distance(FILE *f, const ls_distance_report *d);

/* "name": {tangling metrics}, then ",\n" when comma, else "\n". */
void ls_report_json_tangle(FILE *f, const char *name, const ls_tangle_report *t, int comma);

/* The symmetric distances and tangling of a result as text lines. */
void ls_report_text_distance(FILE *f, const ls_distance_report *d);
void ls_report_text_tangle(FILE *f, const char *name, const ls_tangle_report *t);

/* The finishing of `largesteps fit`'s contact sheet (3 rows of `views`
 * tiles: target, initial, result): each tile labelled "<row> <view>", then
 * the sheet put over a grey checkerboard (ls_contact_backdrop: 8-pixel
 * squares of 0.35 and 0.55) so that a mask fit's white silhouettes show. */
ls_status ls_report_fit_sheet(ls_contact *sheet, uint32_t views);

#endif /* LS_REPORT_H */
