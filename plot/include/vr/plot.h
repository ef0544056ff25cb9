/* Line plots for the tools' HTML reports, drawn with cairo into SVG text
 * that the report embeds inline (one self-contained file, no images
 * beside it). */
#ifndef VR_PLOT_H
#define VR_PLOT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_plot vr_plot;

vr_plot *vr_plot_create(const char *title, const char *xlabel, const char *ylabel);
void vr_plot_destroy(vr_plot *p);
/* A series: points (markers only) or a line.  colour is 0xRRGGBB. */
bool vr_plot_add(vr_plot *p, size_t n, const double *x, const double *y, unsigned colour,
                 bool markers, const char *label);
/* Draws width x height pixels as SVG to f. */
bool vr_plot_write_svg(const vr_plot *p, FILE *f, int width, int height);

#ifdef __cplusplus
}
#endif
#endif
