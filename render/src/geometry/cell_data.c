/* One loaded cell: its arrays in place, its Embree scene, its hits (see
 * cell_data.h). */
#include "geometry/cell_data.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vr/colour.h"

void vr_cell_view_of(const void *payload, const vr_cell_meta *meta, vr_cell_view *v) {
  vr_cell_layout L;
  vr_cell_layout_of(meta->nverts, meta->ntris, meta->nspheres, meta->flags, &L);
  const unsigned char *p = payload;
  v->nverts = meta->nverts;
  v->ntris = meta->ntris;
  v->nspheres = meta->nspheres;
  v->verts = (const float *)(p + L.verts);
  v->normals = (meta->flags & VR_CELL_NORMALS) ? (const float *)(p + L.normals) : NULL;
  v->tris = (const uint32_t *)(p + L.tris);
  v->objects = (const uint32_t *)(p + L.objects);
  v->uv = (const float *)(p + L.uv);
  v->colours = (meta->flags & VR_CELL_COLOURS) ? p + L.colours : NULL;
  v->spheres = (const double *)(p + L.spheres);
  v->sphere_objects = (const uint32_t *)(p + L.sphere_objects);
}

vr_status vr_cell_scene_build(RTCDevice device, const vr_cell_view *v, RTCScene *out,
                              vr_error *err) {
  *out = NULL;
  if (!v->ntris && !v->nspheres) return VR_OK;
  RTCScene scene = rtcNewScene(device);
  if (!scene) return vr_error_set(err, VR_E_NOMEM, "Embree: cannot create a scene");
  /* Robust mode makes the triangle test watertight, so a ray never slips
   * through the shared edge of two triangles. */
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  if (v->ntris) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    /* Both buffers are the cache file's arrays, shared: no copy.  The
     * vertex section has the 16 bytes of padding Embree may read. */
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v->verts, 0,
                               3 * sizeof(float), v->nverts);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, v->tris, 0,
                               3 * sizeof(uint32_t), v->ntris);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, 0);
    rtcReleaseGeometry(geom);
  }
  if (v->nspheres) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float *s = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                       4 * sizeof(float), v->nspheres);
    if (!s) {
      rtcReleaseGeometry(geom);
      rtcReleaseScene(scene);
      return vr_error_set(err, VR_E_NOMEM, "Embree: cannot allocate a sphere buffer");
    }
    for (uint64_t i = 0; i < 4 * v->nspheres; i++) s[i] = (float)v->spheres[i];
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, 1);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(scene);
  enum RTCError e = rtcGetDeviceError(device);
  if (e == RTC_ERROR_OUT_OF_MEMORY) {
    rtcReleaseScene(scene);
    return vr_error_set(err, VR_E_NOMEM,
                        "out of memory while Embree builds a sub-domain of %llu triangles: "
                        "render with --memory-budget below the memory this machine gives "
                        "(and more --subdomains if one does not fit)",
                        (unsigned long long)v->ntris);
  }
  if (e != RTC_ERROR_NONE) {
    rtcReleaseScene(scene);
    return vr_error_set(err, VR_E_NUMERIC, "Embree: error %d while building a sub-domain of %llu "
                        "triangles", (int)e, (unsigned long long)v->ntris);
  }
  *out = scene;
  return VR_OK;
}

static void normalise(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (l > 0)
    for (int a = 0; a < 3; a++) v[a] /= l;
}

static bool has_normal(const float *n) { return n[0] || n[1] || n[2]; }

bool vr_cell_intersect(RTCScene scene, const vr_cell_view *v, const double org[3],
                       const double dir[3], double tnear, double tfar, vr_hit *hit) {
  if (!scene) return false;
  if (!(tfar >= tnear)) return false;
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  struct RTCRayHit rh;
  rh.ray.org_x = (float)org[0];
  rh.ray.org_y = (float)org[1];
  rh.ray.org_z = (float)org[2];
  rh.ray.dir_x = (float)dir[0];
  rh.ray.dir_y = (float)dir[1];
  rh.ray.dir_z = (float)dir[2];
  rh.ray.tnear = (float)tnear;
  rh.ray.tfar = isinf(tfar) ? INFINITY : (float)tfar;
  rh.ray.time = 0.0f;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

  hit->t = rh.ray.tfar;
  for (int a = 0; a < 3; a++) hit->p[a] = org[a] + hit->t * dir[a];
  if (rh.hit.geomID == 0) {
    uint32_t t = rh.hit.primID;
    hit->sphere = false;
    hit->prim = t;
    hit->object = v->objects[t];
    const uint32_t *ix = v->tris + 3 * (size_t)t;
    const float *v0 = v->verts + 3 * (size_t)ix[0], *v1 = v->verts + 3 * (size_t)ix[1],
                *v2 = v->verts + 3 * (size_t)ix[2];
    double e1[3], e2[3];
    for (int a = 0; a < 3; a++) {
      e1[a] = (double)v1[a] - v0[a];
      e2[a] = (double)v2[a] - v0[a];
    }
    hit->ng[0] = e1[1] * e2[2] - e1[2] * e2[1];
    hit->ng[1] = e1[2] * e2[0] - e1[0] * e2[2];
    hit->ng[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double area2 = sqrt(hit->ng[0] * hit->ng[0] + hit->ng[1] * hit->ng[1] + hit->ng[2] * hit->ng[2]);
    normalise(hit->ng);
    double u = rh.hit.u, w2 = rh.hit.v, w = 1.0 - u - w2;
    const float *n0 = NULL, *n1 = NULL, *n2 = NULL;
    if (v->normals) {
      n0 = v->normals + 3 * (size_t)ix[0];
      n1 = v->normals + 3 * (size_t)ix[1];
      n2 = v->normals + 3 * (size_t)ix[2];
    }
    /* A vertex without a normal holds (0,0,0): the triangle is flat then. */
    if (n0 && has_normal(n0) && has_normal(n1) && has_normal(n2)) {
      for (int a = 0; a < 3; a++) hit->ns[a] = w * n0[a] + u * n1[a] + w2 * n2[a];
      normalise(hit->ns);
      /* Interpolated normals may lean across the geometric one; keep the side. */
      if (hit->ns[0] * hit->ng[0] + hit->ns[1] * hit->ng[1] + hit->ns[2] * hit->ng[2] <= 0)
        memcpy(hit->ns, hit->ng, sizeof hit->ns);
    } else {
      memcpy(hit->ns, hit->ng, sizeof hit->ns);
    }
    hit->has_rgb = v->colours != NULL;
    if (v->colours) {
      /* Decoded at the corners, interpolated linearly. */
      const uint8_t *c = v->colours + 9 * (size_t)t;
      for (int a = 0; a < 3; a++)
        hit->rgb[a] = w * vr_srgb_decode(c[a] / 255.0) + u * vr_srgb_decode(c[3 + a] / 255.0) +
                      w2 * vr_srgb_decode(c[6 + a] / 255.0);
    }
    const float *q = v->uv + 6 * (size_t)t;
    hit->uv[0] = w * q[0] + u * q[2] + w2 * q[4];
    hit->uv[1] = w * q[1] + u * q[3] + w2 * q[5];
    double uv2 = fabs(((double)q[2] - q[0]) * ((double)q[5] - q[1]) -
                      ((double)q[4] - q[0]) * ((double)q[3] - q[1]));
    hit->uv_rate = area2 > 0 && isfinite(uv2 / area2) ? sqrt(uv2 / area2) : 0;
    /* e1 = du1 dpdu + dv1 dpdv, e2 = du2 dpdu + dv2 dpdv, solved. */
    double du1 = (double)q[2] - q[0], dv1 = (double)q[3] - q[1], du2 = (double)q[4] - q[0],
           dv2 = (double)q[5] - q[1], det = du1 * dv2 - du2 * dv1;
    if (fabs(det) > 1e-20) {
      for (int a = 0; a < 3; a++) {
        hit->dpdu[a] = (dv2 * e1[a] - dv1 * e2[a]) / det;
        hit->dpdv[a] = (du1 * e2[a] - du2 * e1[a]) / det;
      }
    } else {
      memset(hit->dpdu, 0, sizeof hit->dpdu), memset(hit->dpdv, 0, sizeof hit->dpdv);
    }
  } else {
    uint32_t s = rh.hit.primID;
    const double *sc = v->spheres + 4 * (size_t)s;
    hit->sphere = true;
    hit->has_rgb = false;
    hit->prim = s;
    hit->object = v->sphere_objects[s];
    for (int a = 0; a < 3; a++) hit->ng[a] = hit->p[a] - sc[a];
    normalise(hit->ng);
    memcpy(hit->ns, hit->ng, sizeof hit->ns);
    hit->uv[0] = 0.5 + atan2(hit->ng[1], hit->ng[0]) / (2.0 * M_PI);
    hit->uv[1] = acos(fmax(-1.0, fmin(1.0, hit->ng[2]))) / M_PI;
    /* u spans 2 pi r, v spans pi r: the geometric mean of the rates. */
    hit->uv_rate = sc[3] > 0 ? 1.0 / (M_PI * sc[3] * M_SQRT2) : 0;
    memset(hit->dpdu, 0, sizeof hit->dpdu), memset(hit->dpdv, 0, sizeof hit->dpdv);
  }
  return true;
}
