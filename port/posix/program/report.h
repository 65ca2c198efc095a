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

#endif /* LS_REPORT_H */
