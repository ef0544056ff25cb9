/* vr-hotel: writes a large, real-looking interior for the domain
 * decomposition study (docs/ddm.md): a hotel floor of N rooms along a
 * corridor.  Each room has a bed (mattress, draped duvet, pillows, a
 * tufted headboard), pleated curtains, an armchair, a desk with a chair
 * and a lamp, a floor lamp, a plant and a wardrobe; its window is clear
 * float or electrochromic glass at a tint that changes from room to room;
 * the sun and a CIE clear sky light the floor from the south, and ceiling
 * panels the corridor.  The meshes are written once (binary PLY) and placed
 * in every room, alternate rooms mirrored, so the scene is large in the
 * renderer (every placement is its own triangles) and small on disk.
 *
 *   vr-hotel [--rooms N] [--detail D] OUTDIR
 *
 * writes the meshes in OUTDIR/meshes (with texture coordinates), the wood
 * and fabric images of the furniture in OUTDIR/textures, and two views of
 * the same floor:
 * OUTDIR/hotel.scn from inside the middle room towards its window (the
 * paper's view of a hotel room), and OUTDIR/hotel_corridor.scn down the
 * corridor, where every camera path crosses many sub-domains; it prints the
 * triangle counts.  The default, 24 rooms at detail 100, is 20.5 million triangles.
 * Materials are the database names the main job saves
 * (scripts/main-job.sh), as in samples/room.scn. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hotel_mesh.h"
#include "hotel_textures.h"

typedef struct piece {
  const char *name, *material;
  mesh m;
} piece;

/* ---- the furniture, each about its own footprint, z up, metres ---- */

typedef struct cloth {
  double w, h, depth, folds;
} cloth;

/* A curtain: pleats along its width, deeper at the hem. */
static void curtain_at(const void *ctx, double u, double v, double p[3]) {
  const cloth *c = ctx;
  p[0] = c->w * (u - 0.5);
  p[1] = c->depth * sin(2 * M_PI * c->folds * u) * (0.6 + 0.4 * (1 - v)) +
         0.006 * sin(2 * M_PI * 4.7 * c->folds * u + 3 * v);
  p[2] = 0.05 + c->h * v;
}

/* A duvet over a 2.0 x 1.6 m mattress top at 0.55 m: wrinkled on top,
 * hanging at the sides and the foot. */
static void duvet_at(const void *ctx, double u, double v, double p[3]) {
  (void)ctx;
  double s = 2.6 * u - 1.3, t = 2.2 * v - 1.1; /* beyond the mattress by 0.3 m */
  double hs = 1.0, ht = 0.8;
  double cs = fmax(-hs, fmin(hs, s)), ct = fmax(-ht, fmin(ht, t));
  double over = fmax(fabs(s) - hs, 0) + fmax(fabs(t) - ht, 0);
  double wr = 0.012 * sin(9 * s + 2 * t) * cos(7 * t - s) + 0.006 * sin(23 * s * t);
  p[0] = cs + copysign(0.02 + 0.01 * sin(30 * t), s) * (fabs(s) > hs);
  p[1] = ct + copysign(0.02 + 0.01 * sin(30 * s), t) * (fabs(t) > ht);
  p[2] = 0.57 + wr - over;
  if (s < -hs) p[0] = -hs - 0.02; /* the head end tucks under the pillows */
}

/* A tufted headboard panel in the xz plane. */
static void headboard_at(const void *ctx, double u, double v, double p[3]) {
  (void)ctx;
  p[0] = 1.8 * (u - 0.5);
  double tuft = pow(fabs(cos(M_PI * 8 * u) * cos(M_PI * 5 * v)), 6);
  p[1] = 0.05 - 0.03 * tuft;
  p[2] = 0.5 + 1.0 * v;
}

/* A leaf: a curved blade from the stem at angle a, tilted up by b. */
typedef struct leaf {
  double a, b, len;
} leaf;

static void leaf_at(const void *ctx, double u, double v, double p[3]) {
  const leaf *l = ctx;
  double r = l->len * v, w = 0.05 * sin(M_PI * v) * (u - 0.5);
  double z = 0.45 + r * sin(l->b) - 0.4 * r * r;
  double x = r * cos(l->b);
  p[0] = x * cos(l->a) - w * sin(l->a);
  p[1] = x * sin(l->a) + w * cos(l->a);
  p[2] = z + 0.02 * sin(M_PI * u);
}

static bool make_pieces(piece *P, int D) {
  bool ok = true;
  /* curtains: two panels side by side */
  cloth c = {0.7, 2.35, 0.07, 6}; /* drawn aside: a panel each side of the window */
  for (int k = 0; k < 2 && ok; k++) {
    size_t v0 = P[0].m.nv;
    ok = mesh_grid(&P[0].m, curtain_at, &c, 4 * D, 3 * D, false);
    for (size_t v = v0; v < P[0].m.nv; v++) P[0].m.p[3 * v] += (float)(k ? 1.0 : -1.0);
  }
  /* the bed: mattress, duvet, pillows, frame, headboard */
  ok = ok && mesh_rounded_box(&P[1].m, (double[3]){0, 0, 0.43}, 1.0, 0.8, 0.13, 0.15, D + 28);
  ok = ok && mesh_grid(&P[2].m, duvet_at, NULL, 3 * D, 2 * D, false);
  for (int k = 0; k < 2 && ok; k++)
    ok = mesh_rounded_box(&P[3].m, (double[3]){-0.78, k ? 0.38 : -0.38, 0.62}, 0.2, 0.33, 0.08,
                          0.45, D);
  ok = ok && mesh_box(&P[4].m, (double[3]){-1.05, -0.85, 0.12}, (double[3]){1.05, 0.85, 0.3});
  for (int k = 0; k < 4 && ok; k++) {
    double x = k & 1 ? 0.95 : -0.95, y = k & 2 ? 0.75 : -0.75;
    ok = mesh_box(&P[4].m, (double[3]){x - 0.04, y - 0.04, 0}, (double[3]){x + 0.04, y + 0.04, 0.12});
  }
  size_t h0 = P[5].m.nv;
  ok = ok && mesh_grid(&P[5].m, headboard_at, NULL, 2 * D, D, false);
  for (size_t v = h0; v < P[5].m.nv; v++) { /* stand it at the head, facing the foot */
    float x = P[5].m.p[3 * v], y = P[5].m.p[3 * v + 1];
    P[5].m.p[3 * v] = -1.1f - y;
    P[5].m.p[3 * v + 1] = x;
  }
  /* an armchair: seat, back, two arms */
  ok = ok && mesh_rounded_box(&P[6].m, (double[3]){0, 0, 0.3}, 0.4, 0.4, 0.12, 0.3, D);
  ok = ok && mesh_rounded_box(&P[6].m, (double[3]){0, 0.36, 0.65}, 0.4, 0.1, 0.35, 0.3, D);
  ok = ok && mesh_rounded_box(&P[6].m, (double[3]){-0.45, 0, 0.4}, 0.08, 0.4, 0.22, 0.3, D);
  ok = ok && mesh_rounded_box(&P[6].m, (double[3]){0.45, 0, 0.4}, 0.08, 0.4, 0.22, 0.3, D);
  /* a desk with a drawer block, and its chair */
  ok = ok && mesh_box(&P[7].m, (double[3]){-0.7, -0.35, 0.72}, (double[3]){0.7, 0.35, 0.76});
  for (int k = 0; k < 4 && ok; k++) {
    double x = k & 1 ? 0.64 : -0.64, y = k & 2 ? 0.29 : -0.29;
    ok = mesh_box(&P[7].m, (double[3]){x - 0.03, y - 0.03, 0}, (double[3]){x + 0.03, y + 0.03, 0.72});
  }
  ok = ok && mesh_box(&P[7].m, (double[3]){0.2, -0.33, 0.45}, (double[3]){0.6, 0.33, 0.72});
  ok = ok && mesh_rounded_box(&P[8].m, (double[3]){0, 0, 0.46}, 0.22, 0.22, 0.04, 0.25, D);
  ok = ok && mesh_rounded_box(&P[8].m, (double[3]){0, 0.2, 0.75}, 0.22, 0.03, 0.25, 0.25, D);
  double lr[2] = {0.018, 0.018}, lz[2] = {0, 0.46};
  for (int k = 0; k < 4 && ok; k++)
    ok = mesh_lathe(&P[8].m, k & 1 ? 0.18 : -0.18, k & 2 ? 0.18 : -0.18, lr, lz, 2, 3 * D / 8 + 4,
                    2 * D / 8 + 2);
  /* a floor lamp and a desk lamp, turned */
  double fr[9] = {0.001, 0.16, 0.16, 0.02, 0.015, 0.015, 0.12, 0.22, 0.001},
         fz[9] = {0.0, 0.0, 0.03, 0.05, 0.1, 1.35, 1.35, 1.65, 1.66};
  ok = ok && mesh_lathe(&P[9].m, 0, 0, fr, fz, 9, 5 * D / 2, D / 2 + 14);
  double dr[7] = {0.001, 0.08, 0.08, 0.012, 0.012, 0.12, 0.05},
         dz[7] = {0.0, 0.0, 0.02, 0.03, 0.35, 0.38, 0.55};
  ok = ok && mesh_lathe(&P[10].m, 0, 0, dr, dz, 7, 2 * D, D / 2);
  /* a plant: a pot and forty leaves */
  double pr[5] = {0.001, 0.12, 0.16, 0.15, 0.001}, pz[5] = {0, 0, 0.42, 0.44, 0.44};
  ok = ok && mesh_lathe(&P[11].m, 0, 0, pr, pz, 5, 2 * D, D / 4 + 4);
  for (int k = 0; k < 40 && ok; k++) {
    leaf l = {2.399963 * k, 0.5 + 0.8 * ((k * 37) % 11) / 11.0, 0.35 + 0.25 * ((k * 13) % 7) / 7.0};
    ok = mesh_grid(&P[12].m, leaf_at, &l, D / 10 + 2, D / 2, false);
  }
  /* a wardrobe */
  ok = ok && mesh_box(&P[13].m, (double[3]){-0.5, -0.3, 0}, (double[3]){0.5, 0.3, 2.2});
  for (int i = 0; i < 14; i++) {
    mesh_drop_degenerate(&P[i].m);
    mesh_normals(&P[i].m);
  }
  return ok;
}

/* ---- the scene ---- */

/* Where each piece stands in a room: room-local x in [0, 4] (west to
 * east), y in [0, 5] from the window wall to the door wall; rotation about
 * z in degrees. */
static const struct {
  int piece;
  double x, y, rot;
} PLACE[] = {
    {0, 2.0, 0.12, 0},                                            /* curtains at the window */
    {1, 1.25, 3.6, -90}, {2, 1.25, 3.6, -90}, {3, 1.25, 3.6, -90}, /* bed, head to the door wall */
    {4, 1.25, 3.6, -90}, {5, 1.25, 3.6, -90},
    {6, 3.2, 1.0, -150},                                          /* armchair by the window */
    {7, 3.55, 2.6, 90}, {8, 3.0, 2.6, -90},                       /* desk and its chair */
    {9, 0.35, 0.6, 0}, {10, 3.6, 2.2, 0},                         /* lamps */
    {11, 0.4, 1.5, 0}, {12, 0.4, 1.5, 0},                         /* plant */
    {13, 3.45, 4.6, 0},                                           /* wardrobe by the door */
};

static void rect(FILE *f, double cx, double cy, double cz, const char *n, double w, double h,
                 const char *mat, const char *extra) {
  fprintf(f, "rect center=%.3f,%.3f,%.3f normal=%s size=%.3f,%.3f material=%s%s\n", cx, cy, cz, n,
          w, h, mat, extra ? extra : "");
}

static void room(FILE *f, int i, int nrooms) {
  double X = 4.0 * i;
  bool mirror = i & 1;
  fprintf(f, "\n# room %d\n", i + 1);
  rect(f, X + 2, -2.5, 0, "0,0,1", 4, 5, "carpet", NULL);
  rect(f, X + 2, -2.5, 2.7, "0,0,-1", 4, 5, "paint", NULL);
  rect(f, X, -2.5, 1.35, "1,0,0", 5, 2.7, "paint", NULL); /* the wall to the west */
  if (i == nrooms - 1) rect(f, X + 4, -2.5, 1.35, "-1,0,0", 5, 2.7, "paint", NULL);
  /* the window wall: sill, lintel, piers, and the pane */
  rect(f, X + 2, -5, 0.4, "0,1,0", 4, 0.8, "paint", NULL);
  rect(f, X + 2, -5, 2.5, "0,1,0", 4, 0.4, "paint", NULL);
  rect(f, X + 0.4, -5, 1.55, "0,1,0", 0.8, 1.5, "paint", NULL);
  rect(f, X + 3.6, -5, 1.55, "0,1,0", 0.8, 1.5, "paint", NULL);
  const char *glass = i % 4 == 0 ? "clear" : (const char *[]){"", "ec1", "ec2", "ec3"}[i % 4];
  rect(f, X + 2, -5, 1.55, "0,1,0", 2.4, 1.5, glass, NULL);
  /* the door wall, with the door open onto the corridor */
  double d0 = mirror ? 0.2 : 2.9, d1 = d0 + 0.9;
  rect(f, X + d0 / 2, 0, 1.35, "0,-1,0", d0, 2.7, "paint", NULL);
  rect(f, X + (d1 + 4) / 2, 0, 1.35, "0,-1,0", 4 - d1, 2.7, "paint", NULL);
  rect(f, X + (d0 + d1) / 2, 0, 2.4, "0,-1,0", 0.9, 0.6, "paint", NULL);
  static const char *mats[14] = {"fabric", "cotton", "fabric", "cotton", "wood", "fabric", "fabric",
                                 "wood",   "wood",   "alu",    "alu",    "concrete", "leaf", "wood"};
  static const char *names[14] = {"curtains", "mattress", "duvet", "pillows", "bedframe",
                                  "headboard", "armchair", "desk", "chair", "floorlamp",
                                  "desklamp", "pot", "leaves", "wardrobe"};
  for (size_t k = 0; k < sizeof PLACE / sizeof PLACE[0]; k++) {
    double x = mirror ? 4 - PLACE[k].x : PLACE[k].x, rot = mirror ? -PLACE[k].rot : PLACE[k].rot;
    fprintf(f, "mesh meshes/%s.ply material=%s %srotate=0,0,1,%g translate=%.3f,%.3f,0\n",
            names[PLACE[k].piece], mats[PLACE[k].piece], mirror ? "scale=-1,1,1 " : "", rot, X + x,
            -5 + PLACE[k].y);
  }
}

/* One view of the floor: view 0 from inside the middle room, 1 down the
 * corridor. */
static bool write_scene(const char *path, int view, int nrooms, int D, size_t per_room) {
  FILE *f = fopen(path, "w");
  if (!f) return false;
  double L = 4.0 * nrooms, X = 4.0 * (nrooms / 2);
  fprintf(f,
          "# A hotel floor of %d rooms along a corridor, written by vr-hotel --rooms %d --detail %d\n"
          "# (samples/hotel/hotel_gen.c): %zu triangles of furniture per room, %zu in all.\n"
          "# Rooms are 4 x 5 x 2.7 m, windows to the south (y = -5), doors onto the corridor\n"
          "# (y = 0 to 2).  Materials come from the database the main job fills.\n\n",
          nrooms, nrooms, D, per_room, per_room * (size_t)nrooms);
  if (view == 0)
    fprintf(f, "# Room %d, from beside the wardrobe towards the window and the bed.\n"
            "camera pinhole from=%.2f,-0.6,1.7 to=%.2f,-4.5,0.7 fov=80 resolution=320x240 exposure=-3\n\n",
            nrooms / 2 + 1, X + ((nrooms / 2) & 1 ? 1.1 : 2.9), X + ((nrooms / 2) & 1 ? 2.8 : 1.2));
  else
    fprintf(f, "# Down the corridor.\n"
            "camera pinhole from=0.6,1.0,1.6 to=%.1f,0.6,1.2 fov=75 resolution=320x240 exposure=-1\n\n",
            L);
  fputs("material paint    db:photo-paint\n"
        "material carpet   db:photo-carpet\n"
        "material cotton   db:photo-cotton\n"
        "material pine     db:photo-pine\n"
        "material concrete db:photo-concrete\n"
        "material brick    db:photo-brick\n"
        "material leaf     lambert reflectance=0.15\n"
        "material alu      db:Al roughness=0.25\n"
        "material clear    db:clear-float-nk thickness=4mm model=thin\n"
        "material ec1      db:electrochromic-glass state=0.3\n"
        "material ec2      db:electrochromic-glass state=0.6\n"
        "material ec3      db:electrochromic-glass state=0.9\n"
        "material panel    lambert reflectance=0.8\n"
        "# Textured furniture (vr-hotel's images): boxes carry metres as (u, v),\n"
        "# so tile=1 is one image a metre; curved pieces span the image once.\n"
        "material wood     lambert texture=textures/wood.png tile=1\n"
        "material fabric   lambert texture=textures/fabric.png tile=6\n\n"
        "# The corridor, its ceiling panels lit.\n",
        f);
  rect(f, L / 2, 1, 0, "0,0,1", L, 2, "carpet", NULL);
  rect(f, L / 2, 1, 2.7, "0,0,-1", L, 2, "paint", NULL);
  rect(f, L / 2, 2, 1.35, "0,-1,0", L, 2.7, "brick", NULL);
  rect(f, 0, 1, 1.35, "1,0,0", 2, 2.7, "paint", NULL);
  rect(f, L, 1, 1.35, "-1,0,0", 2, 2.7, "paint", NULL);
  for (int i = 0; i < nrooms; i += 2)
    rect(f, 4.0 * i + 4, 1, 2.69, "0,0,-1", 0.6, 0.6, "panel",
         " emission=800cd/m2 emission_spectrum=LED-B3");
  for (int i = 0; i < nrooms; i++) room(f, i, nrooms);
  fprintf(f, "\n# Daylight from the south.\n"
             "light sun altitude=35 azimuth=180 illuminance=80000lx\n"
             "sky cie type=12 illuminance=15000lx\n\n"
             "render integrator=path spp=8 depth=5\n");
  return fclose(f) == 0;
}

static int usage(void) {
  fputs("usage: vr-hotel [--rooms N] [--detail D] OUTDIR\n"
        "  writes OUTDIR/hotel.scn, OUTDIR/meshes/*.ply and OUTDIR/textures/*.png: a hotel floor of N rooms\n"
        "  (default 24) whose furniture is tessellated at detail D (default 100;\n"
        "  triangles grow as D^2): 24 rooms at 100 are 20.5 million triangles.\n",
        stderr);
  return 2;
}

int main(int argc, char **argv) {
  int nrooms = 24, D = 100;
  const char *out = NULL;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--rooms") && i + 1 < argc)
      nrooms = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--detail") && i + 1 < argc)
      D = atoi(argv[++i]);
    else if (argv[i][0] == '-' || out)
      return usage();
    else
      out = argv[i];
  }
  if (!out || nrooms < 1 || nrooms > 10000 || D < 8 || D > 2000) return usage();
  char path[4200], tex[4200];
  snprintf(path, sizeof path, "%s/meshes", out);
  snprintf(tex, sizeof tex, "%s/textures", out);
  if ((mkdir(out, 0755) && errno != EEXIST) || (mkdir(path, 0755) && errno != EEXIST) ||
      (mkdir(tex, 0755) && errno != EEXIST)) {
    fprintf(stderr, "vr-hotel: cannot create %s: %s\n", path, strerror(errno));
    return 1;
  }
  if (!hotel_write_textures(tex)) return 1;
  static piece P[14] = {{"curtains", "cotton", {0}}, {"mattress", "cotton", {0}},
                        {"duvet", "cotton", {0}},    {"pillows", "cotton", {0}},
                        {"bedframe", "pine", {0}},   {"headboard", "cotton", {0}},
                        {"armchair", "cotton", {0}}, {"desk", "pine", {0}},
                        {"chair", "pine", {0}},      {"floorlamp", "alu", {0}},
                        {"desklamp", "alu", {0}},    {"pot", "concrete", {0}},
                        {"leaves", "leaf", {0}},     {"wardrobe", "pine", {0}}};
  if (!make_pieces(P, D)) {
    fputs("vr-hotel: out of memory\n", stderr);
    return 1;
  }
  size_t per_room = 0;
  for (int i = 0; i < 14; i++) {
    snprintf(path, sizeof path, "%s/meshes/%s.ply", out, P[i].name);
    if (!mesh_write_ply(&P[i].m, path)) {
      fprintf(stderr, "vr-hotel: cannot write %s: %s\n", path, strerror(errno));
      return 1;
    }
  }
  for (size_t k = 0; k < sizeof PLACE / sizeof PLACE[0]; k++) per_room += P[PLACE[k].piece].m.nt;
  for (int view = 0; view < 2; view++) {
    snprintf(path, sizeof path, "%s/%s", out, view ? "hotel_corridor.scn" : "hotel.scn");
    if (!write_scene(path, view, nrooms, D, per_room)) {
      fprintf(stderr, "vr-hotel: cannot write %s: %s\n", path, strerror(errno));
      return 1;
    }
  }
  size_t on_disk = 0;
  for (int i = 0; i < 14; i++) on_disk += P[i].m.nv * 32 + P[i].m.nt * 13;
  printf("vr-hotel: %d rooms, %zu triangles per room, %zu in all; meshes %.1f MiB on disk; "
         "%s/hotel.scn and %s/hotel_corridor.scn\n",
         nrooms, per_room, per_room * (size_t)nrooms, on_disk / 1048576.0, out, out);
  for (int i = 0; i < 14; i++) mesh_free(&P[i].m);
  return 0;
}
