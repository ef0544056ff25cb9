/* Specular T and R tables of panes (vr/btdf_table.h). */
#include "vr/btdf_table.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/optics.h"

void vr_btdf_table_free(vr_btdf_table *t) {
  if (!t) return;
  free(t->angles);
  free(t->nm);
  for (int i = 0; i < VR_BT_COUNT; i++) free(t->q[i]);
  memset(t, 0, sizeof *t);
}

static vr_status table_alloc(vr_btdf_table *t, const double *angles, size_t na, const double *nm,
                             size_t nl, vr_error *err) {
  memset(t, 0, sizeof *t);
  if (na == 0 || nl == 0) return vr_error_set(err, VR_E_ARG, "empty angle or wavelength list");
  for (size_t i = 0; i < na; i++)
    if (!(angles[i] >= 0 && angles[i] <= 90) || (i && !(angles[i] > angles[i - 1])))
      return vr_error_set(err, VR_E_ARG, "angles must increase within [0, 90] degrees (%g)", angles[i]);
  for (size_t j = 0; j < nl; j++)
    if (!(nm[j] > 0) || (j && !(nm[j] > nm[j - 1])))
      return vr_error_set(err, VR_E_ARG, "wavelengths must be positive and increase (%g nm)", nm[j]);
  t->na = na;
  t->nl = nl;
  t->angles = malloc(na * sizeof *t->angles);
  t->nm = malloc(nl * sizeof *t->nm);
  bool ok = t->angles && t->nm;
  for (int i = 0; i < VR_BT_COUNT; i++) ok = ok && (t->q[i] = malloc(na * nl * sizeof(double)));
  if (!ok) {
    vr_btdf_table_free(t);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  memcpy(t->angles, angles, na * sizeof *angles);
  memcpy(t->nm, nm, nl * sizeof *nm);
  return VR_OK;
}

vr_status vr_btdf_from_material(const vr_material *m, double thickness_nm, const double *angles,
                                size_t na, const double *nm, size_t nl, vr_btdf_table *out,
                                vr_error *err) {
  if (!(thickness_nm > 0))
    return vr_error_set(err, VR_E_ARG, "material %s: a pane thickness is needed (--thickness MM)",
                        m->name);
  vr_status st = table_alloc(out, angles, na, nm, nl, err);
  if (st) return st;
  out->thickness_nm = thickness_nm;
  snprintf(out->method, sizeof out->method,
           "thick slab of %s (%g mm), Fresnel per polarisation, all internal reflections", m->name,
           thickness_nm * 1e-6);
  for (size_t j = 0; j < nl && !st; j++) {
    double n, k;
    st = vr_material_nk(m, nm[j], false, &n, &k, NULL, err);
    for (size_t i = 0; i < na && !st; i++) {
      vr_slab_result s;
      st = vr_slab(1.0, n + I * k, thickness_nm, angles[i] * M_PI / 180, nm[j], &s, err);
      size_t at = i * nl + j;
      for (int p = 0; p < 2 && !st; p++) {
        out->q[VR_BT_TS + p][at] = s.T[p];
        out->q[VR_BT_RFS + p][at] = s.R[p];
        out->q[VR_BT_RBS + p][at] = s.R[p]; /* a bare slab is symmetric */
      }
    }
  }
  if (st) vr_btdf_table_free(out);
  return st;
}

/* The coated pane as a vr_layer stack at one wavelength: air, the films,
 * the incoherent substrate, air; reversed for light from the back. */
static vr_status model_stack(const vr_sample_model *m, double nm, bool reversed, vr_layer *L,
                             size_t *count, vr_error *err) {
  size_t n = m->nlayers + 3;
  vr_complex amb;
  vr_status st = vr_dispersion_index(m->ambient, nm, &amb, err);
  if (st) return st;
  L[0] = (vr_layer){amb, 0, 0};
  for (size_t i = 0; i < m->nlayers && !st; i++) {
    vr_complex N;
    st = vr_model_layer_index(m, (long)i, nm, &N, err);
    L[1 + i] = (vr_layer){N, m->layers[i].thickness_nm, 0};
  }
  vr_complex sub;
  if (!st) st = vr_model_layer_index(m, -1, nm, &sub, err);
  if (st) return st;
  L[n - 2] = (vr_layer){sub, m->substrate_thickness_nm, 1};
  L[n - 1] = (vr_layer){amb, 0, 0};
  if (reversed)
    for (size_t i = 0; i < n / 2; i++) {
      vr_layer t = L[i];
      L[i] = L[n - 1 - i];
      L[n - 1 - i] = t;
    }
  *count = n;
  return VR_OK;
}

vr_status vr_btdf_from_model(const vr_sample_model *m, const double *angles, size_t na,
                             const double *nm, size_t nl, vr_btdf_table *out, vr_error *err) {
  if (!(m->substrate_thickness_nm > 0) || !m->backside)
    return vr_error_set(err, VR_E_ARG,
                        "a pane model needs \"substrate MATERIAL thickness=MM backside\" (the glass "
                        "is an incoherent slab with a reflecting back face)");
  vr_status st = table_alloc(out, angles, na, nm, nl, err);
  if (st) return st;
  out->thickness_nm = m->substrate_thickness_nm;
  snprintf(out->method, sizeof out->method,
           "%zu coherent film(s) on a %g mm incoherent substrate (transfer matrices, power sums)",
           m->nlayers, m->substrate_thickness_nm * 1e-6);
  vr_layer *L = malloc((m->nlayers + 3) * sizeof *L);
  if (!L) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t j = 0; j < nl && !st; j++)
    for (int side = 0; side < 2 && !st; side++) {
      size_t count;
      st = model_stack(m, nm[j], side == 1, L, &count, err);
      for (size_t i = 0; i < na && !st; i++)
        for (int p = 0; p < 2 && !st; p++) {
          vr_tmm_result r;
          st = vr_stack_solve(L, count, angles[i] * M_PI / 180, nm[j], (vr_pol)p, &r, err);
          size_t at = i * nl + j;
          if (side == 0) {
            out->q[VR_BT_TS + p][at] = r.T;
            out->q[VR_BT_RFS + p][at] = r.R;
          } else {
            out->q[VR_BT_RBS + p][at] = r.R;
          }
        }
    }
  free(L);
  if (st) vr_btdf_table_free(out);
  return st;
}

vr_status vr_btdf_from_curve(const vr_spectro_curve *c, double thickness_nm,
                             vr_angular_route route, double solar_T0, const double *angles,
                             size_t na, vr_btdf_table *out, vr_error *err) {
  double *nm = malloc(c->n * sizeof *nm);
  if (!nm) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t j = 0; j < c->n; j++) nm[j] = c->p[j].nm;
  vr_status st = table_alloc(out, angles, na, nm, c->n, err);
  free(nm);
  if (st) return st;
  out->thickness_nm = thickness_nm;
  vr_angular_route used = VR_ROUTE_AUTO;
  for (size_t i = 0; i < na && !st; i++) {
    vr_pane *p = NULL;
    st = vr_pane_from_curve(c, thickness_nm, angles[i], route, solar_T0, &p, NULL, err);
    for (size_t j = 0; j < c->n && !st; j++)
      for (int pol = 0; pol < 2; pol++) {
        out->q[VR_BT_TS + pol][i * c->n + j] = p->T[pol][j];
        out->q[VR_BT_RFS + pol][i * c->n + j] = p->Rf[pol][j];
        out->q[VR_BT_RBS + pol][i * c->n + j] = p->Rb[pol][j];
      }
    if (p && p->route != VR_ROUTE_AUTO) used = p->route;
    vr_pane_destroy(p);
  }
  snprintf(out->method, sizeof out->method, "%s",
           used == VR_ROUTE_COATED
               ? "measured T0, R0; Windows-CalcEngine coated-glass polynomials (s = p)"
               : "measured T0, R0; physical route: n, k back-solved, Fresnel per polarisation");
  if (st) vr_btdf_table_free(out);
  return st;
}

vr_status vr_btdf_table_material(const vr_btdf_table *t, const char *name, vr_material **out,
                                 vr_error *err) {
  static const char *const Q[VR_BT_COUNT] = {"Ts", "Tp", "Rfs", "Rfp", "Rbs", "Rbp"};
  *out = NULL;
  vr_material *m = vr_material_create(name, VR_KIND_BTDF, err);
  if (!m) return err ? err->status : VR_E_NOMEM;
  vr_status st = VR_OK;
  char role[32], *list = malloc(t->na * 24 + 1);
  if (!list) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t used = 0;
  for (size_t i = 0; i < t->na && !st; i++) {
    used += (size_t)sprintf(list + used, "%s%g", i ? "," : "", t->angles[i]);
    for (int q = 0; q < VR_BT_COUNT && !st; q++) {
      snprintf(role, sizeof role, "%s@%g", Q[q], t->angles[i]);
      vr_spectrum *s = vr_spectrum_create(t->nl, t->nm, t->q[q] + i * t->nl, err);
      st = s ? vr_material_add_spectrum(m, role, s, err) : (err ? err->status : VR_E_NOMEM);
    }
  }
  if (!st) st = vr_material_add_property(m, "angles", list, NAN, "deg", err);
  if (!st && t->thickness_nm > 0)
    st = vr_material_add_property(m, "thickness", NULL, t->thickness_nm * 1e-6, "mm", err);
  if (!st) st = vr_material_set_text(&m->prov.model, t->method, err);
  free(list);
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  *out = m;
  return VR_OK;
}
