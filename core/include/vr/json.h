/* The two pieces every tool needs to print JSON by hand: strings with the
 * escapes RFC 8259 requires, and numbers (non-finite ones become null). */
#ifndef VR_JSON_H
#define VR_JSON_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

void vr_json_string(FILE *f, const char *s); /* NULL prints null */
void vr_json_number(FILE *f, double v);      /* %.17g; NaN and inf print null */

#ifdef __cplusplus
}
#endif
#endif
