/* Radiance primitives read as the model's (rad_read.h): a material
 * definition's checks and what it records, and a surface's triangles
 * placed by its file's transform. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geometry/rad_parse.h"

/* A material definition. */
vr_status rad_material(reader *r, src *f, prim *p, vr_rad_kind kind) {
  if (strcmp(p->mod, "void"))
    return rad_fail(r, f, p->line,
                "%s '%s': its modifier '%s' is not void; patterns and textures are not read "
                "(map the material with material.%s=NAME in the scene)",
                p->type, p->id, p->mod, p->id);
  static const long want[] = {[VR_RAD_PLASTIC] = 5, [VR_RAD_METAL] = 5, [VR_RAD_MIRROR] = 3,
                              [VR_RAD_GLASS] = 3,   [VR_RAD_DIELECTRIC] = 5, [VR_RAD_LIGHT] = 3,
                              [VR_RAD_GLOW] = 4,    [VR_RAD_BSDF] = 0, [VR_RAD_TRANS] = 7};
  bool nreal_ok = p->nreal == want[kind] || (kind == VR_RAD_GLASS && p->nreal == 4);
  if (!nreal_ok)
    return rad_fail(r, f, p->line, "%s '%s': %ld real arguments, %s takes %ld%s", p->type, p->id,
                p->nreal, p->type, want[kind],
                kind == VR_RAD_GLASS ? " or 4"
                : kind == VR_RAD_BSDF ? " here (its extra diffuse components are not read)"
                                      : "");
  if (kind != VR_RAD_BSDF && p->nstr)
    return rad_fail(r, f, p->line, "%s '%s': %ld string arguments (%s takes none here%s)", p->type,
                p->id, p->nstr, p->type,
                kind == VR_RAD_MIRROR ? "; a mirror's alternate material is not read" : "");
  vr_rad_material mt;
  memset(&mt, 0, sizeof mt);
  mt.kind = kind;
  snprintf(mt.where, sizeof mt.where, "%s:%ld", f->path, p->line);
  bool found;
  rad_lookup(r, p->id, &found);
  if (found) snprintf(mt.name, sizeof mt.name, "%.100s@%ld", p->id, p->line);
  else snprintf(mt.name, sizeof mt.name, "%s", p->id);
  for (long i = 0; i < p->nreal && i < 7; i++) mt.arg[i] = p->real[i];
  if (kind == VR_RAD_GLASS && p->nreal == 3) mt.arg[3] = 1.52;
  if (kind == VR_RAD_BSDF) {
    if (p->nstr < 6)
      return rad_fail(r, f, p->line,
                  "BSDF '%s': %ld string arguments; it takes 6 (thickness, XML file, up vector x "
                  "y z, function file)", p->id, p->nstr);
    if (p->nstr > 6)
      return rad_fail(r, f, p->line, "BSDF '%s': a transform after the function file is not read",
                  p->id);
    double thick;
    if (!rad_to_real(p->str[0], &thick) || thick != 0)
      return rad_fail(r, f, p->line,
                  "BSDF '%s': thickness '%s': only 0 is read (a thick BSDF's proxy geometry is "
                  "not modelled)", p->id, p->str[0]);
    for (int k = 0; k < 3; k++)
      if (!rad_to_real(p->str[2 + k], &mt.up[k]))
        return rad_fail(r, f, p->line, "BSDF '%s': up vector component '%s' is not a number", p->id,
                    p->str[2 + k]);
    if (strcmp(p->str[5], "."))
      return rad_fail(r, f, p->line,
                  "BSDF '%s': function file '%s' is not read (only '.', no function file)", p->id,
                  p->str[5]);
    vr_xform_vector(&f->x, mt.up, mt.up);
    const char *slash = strrchr(f->path, '/');
    int dir = p->str[1][0] == '/' || !slash ? 0 : (int)(slash - f->path + 1);
    snprintf(mt.file, sizeof mt.file, "%.*s%s", dir, f->path, p->str[1]);
  }
  if (r->walk_only) return VR_OK;
  vr_rad_model *m = r->m;
  vr_rad_material *g = realloc(m->mats, (m->nmats + 1) * sizeof *g);
  if (!g) return rad_nomem(r->err);
  m->mats = g;
  g[m->nmats] = mt;
  return rad_define(r, p->id, (int)m->nmats++);
}

/* Places the triangles appended since nv, nt through the file's transform,
 * turned round when flip. */
static void place(vr_mesh_data *mesh, const src *f, size_t nv, size_t nt, bool flip) {
  for (size_t i = nv; i < mesh->nverts; i++) vr_xform_point(&f->x, mesh->pos + 3 * i, mesh->pos + 3 * i);
  if (!flip) return;
  for (size_t t = nt; t < mesh->ntris; t++) {
    uint32_t s = mesh->tris[3 * t + 1];
    mesh->tris[3 * t + 1] = mesh->tris[3 * t + 2];
    mesh->tris[3 * t + 2] = s;
  }
}

static double len3(const double *v) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* A surface: its material, then its triangles. */
vr_status rad_surface(reader *r, src *f, prim *p) {
  static const struct {
    const char *type;
    long nreal;
  } K[] = {{"polygon", -1}, {"sphere", 4}, {"bubble", 4}, {"cone", 8}, {"cup", 8},
           {"cylinder", 7}, {"tube", 7},   {"ring", 8},   {"source", 4}};
  size_t k = 0;
  while (strcmp(K[k].type, p->type)) k++;
  if (p->nstr)
    return rad_fail(r, f, p->line, "%s '%s': %ld string arguments (it takes none)", p->type, p->id,
                p->nstr);
  if (K[k].nreal >= 0 && p->nreal != K[k].nreal)
    return rad_fail(r, f, p->line, "%s '%s': %ld real arguments, it takes %ld", p->type, p->id,
                p->nreal, K[k].nreal);
  if (K[k].nreal < 0 && (p->nreal < 9 || p->nreal % 3))
    return rad_fail(r, f, p->line,
                "polygon '%s': %ld real arguments; it takes 3 per vertex and at least 3 vertices",
                p->id, p->nreal);
  const double *a = p->real;
  const char *modname = f->mod[0] ? f->mod : p->mod;
  if (!strcmp(modname, "void"))
    return rad_fail(r, f, p->line, "%s '%s': its modifier is void (no material)", p->type, p->id);
  bool found;
  int mat = rad_lookup(r, modname, &found);
  if (!found && !r->walk_only)
    return rad_fail(r, f, p->line, "%s '%s': its modifier '%s' is not defined before it", p->type,
                p->id, modname);
  if (r->walk_only) return VR_OK;
  vr_rad_model *m = r->m;
  if (!strcmp(p->type, "source")) {
    if (mat < 0 || m->mats[mat].kind != VR_RAD_LIGHT)
      return rad_fail(r, f, p->line,
                  "source '%s': its modifier '%s' is not a light (a glow or illum source, a sky, "
                  "is given by the scene's sky line)", p->id, modname);
    if (a[3] >= 180)
      return rad_fail(r, f, p->line,
                  "source '%s': %g deg wide, a sky or a ground: give it in the scene's sky line "
                  "(sources narrower than 180 deg are read, as the sun)", p->id, a[3]);
    if (!(len3(a) > 0) || !(a[3] > 0))
      return rad_fail(r, f, p->line, "source '%s': direction (%g %g %g) or angle %g deg is not valid",
                  p->id, a[0], a[1], a[2], a[3]);
    vr_rad_source *s = realloc(m->src, (m->nsrc + 1) * sizeof *s);
    if (!s) return rad_nomem(r->err);
    m->src = s;
    vr_rad_source *o = &s[m->nsrc++];
    vr_xform_vector(&f->x, a, o->dir);
    double l = len3(o->dir);
    for (int q = 0; q < 3; q++) o->dir[q] /= l;
    o->angle_deg = a[3];
    o->material = mat;
    snprintf(o->where, sizeof o->where, "%s:%ld", f->path, p->line);
    return VR_OK;
  }
  if (mat < 0) {
    m->illum_dropped++;
    return VR_OK;
  }
  size_t nv = m->mesh.nverts, nt = m->mesh.ntris;
  vr_status st = VR_OK;
  vr_error e = {0};
  const char *t = p->type;
  bool out = !strcmp(t, "sphere") || !strcmp(t, "cone") || !strcmp(t, "cylinder");
  if (!strcmp(t, "polygon")) {
    bool degenerate;
    st = vr_rad_polygon(&m->mesh, a, (size_t)p->nreal / 3, (uint32_t)mat, &degenerate, &e);
    m->degenerate += degenerate;
    if (!st && m->mesh.ntris > nt) {
      vr_rad_poly *g = realloc(m->polys, (m->npolys + 1) * sizeof *g);
      if (!g) return rad_nomem(r->err);
      m->polys = g;
      vr_rad_poly *q = &g[m->npolys++];
      snprintf(q->id, sizeof q->id, "%s", p->id);
      snprintf(q->where, sizeof q->where, "%s:%ld", f->path, p->line);
      q->first = nt, q->count = m->mesh.ntris - nt;
    }
  } else if (!strcmp(t, "sphere") || !strcmp(t, "bubble")) {
    if (!(a[3] != 0)) return rad_fail(r, f, p->line, "%s '%s': radius 0", t, p->id);
    /* A negative radius turns the surface inside out, as in Radiance. */
    st = vr_rad_sphere(&m->mesh, a, fabs(a[3]), out == (a[3] > 0), (uint32_t)mat, &e);
  } else if (!strcmp(t, "ring")) {
    if (!(len3(a + 3) > 0) || !(a[6] >= 0) || !(a[7] > a[6]))
      return rad_fail(r, f, p->line,
                  "ring '%s': the normal must not be 0 and the radii 0 <= r0 < r1 (%g, %g)",
                  p->id, a[6], a[7]);
    st = vr_rad_ring(&m->mesh, a, a + 3, a[6], a[7], (uint32_t)mat, &e);
  } else {
    bool cyl = !strcmp(t, "cylinder") || !strcmp(t, "tube");
    double r0 = a[6], r1 = cyl ? a[6] : a[7];
    double ax[3] = {a[3] - a[0], a[4] - a[1], a[5] - a[2]};
    if (!(len3(ax) > 0))
      return rad_fail(r, f, p->line, "%s '%s': its two ends are the same point", t, p->id);
    if (!(r0 >= 0 && r1 >= 0 && r0 + r1 > 0) || (cyl && !(r0 > 0)))
      return rad_fail(r, f, p->line, "%s '%s': radii %g, %g (they must not be negative, nor both 0)",
                  t, p->id, r0, r1);
    st = vr_rad_cone(&m->mesh, a, a + 3, r0, r1, out, (uint32_t)mat, &e);
  }
  if (st) return vr_error_at(r->err, st, f->path, p->line, 0, "%s '%s': %s", t, p->id, e.message);
  /* A mirroring transform turns the triangles round to keep their side;
   * so does a BSDF material: Radiance reads a BSDF XML file with its front
   * and back "reversed from WINDOW 6 orientations" (its bsdf_m.c), so a
   * Radiance BSDF surface's normal faces the file's back, where the
   * renderer's faces the file's front. */
  place(&m->mesh, f, nv, nt, f->flip != (m->mats[mat].kind == VR_RAD_BSDF));
  m->mats[mat].triangles += m->mesh.ntris - nt;
  return VR_OK;
}

