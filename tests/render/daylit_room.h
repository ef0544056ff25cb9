/* The daylit room of issue 17, shared by tests/render/test_photon_sensors.c
 * and bench/bench_daylight.c: 4 x 4 x 3 m, the south wall y = 0 with a
 * 2 x 1.2 m opening, sun at 35 degrees in the south (80 000 lx) and a CIE
 * clear sky (15 000 lx), floor sensors on a 4 x 4 grid, north-wall sensors
 * on 3 x 2, a desk point in mid-air: 23 points.  A printf format: the first
 * %s is the outdoor ground's line (or ""), the second the render options. */
#ifndef VR_DAYLIT_ROOM_H
#define VR_DAYLIT_ROOM_H

#define DAYLIT_ROOM_POINTS 23

/* The room's shell alone: its materials and its nine rects. */
#define DAYLIT_ROOM_SHELL                                                                          \
  "material wall lambert reflectance=0.5\n"                                                        \
  "material floor lambert reflectance=0.3\n"                                                       \
  "rect center=2,2,0   normal=0,0,1  size=4,4 material=floor\n"                                    \
  "rect center=2,2,3   normal=0,0,-1 size=4,4 material=wall\n"                                     \
  "rect center=2,4,1.5 normal=0,-1,0 size=4,3 material=wall\n"                                     \
  "rect center=0,2,1.5 normal=1,0,0  size=4,3 material=wall\n"                                     \
  "rect center=4,2,1.5 normal=-1,0,0 size=4,3 material=wall\n"                                     \
  "rect center=2,0,0.45 normal=0,1,0 size=4,0.9 material=wall\n"                                   \
  "rect center=2,0,2.55 normal=0,1,0 size=4,0.9 material=wall\n"                                   \
  "rect center=0.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall\n"                                  \
  "rect center=3.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall\n"

static const char DAYLIT_ROOM[] =
    DAYLIT_ROOM_SHELL
    "material ground lambert reflectance=0.2\n"
    "%s"
    "light sun altitude=35 azimuth=180 illuminance=80000lx spectrum=D65\n"
    "sky cie type=12 illuminance=15000lx spectrum=D65\n"
    "sensor floor grid origin=0.05,0.05,0.001 u=3.9,0,0 v=0,3.9,0 n=4,4 normal=0,0,1\n"
    "sensor wall grid origin=0.5,3.999,0.5 u=3,0,0 v=0,0,2 n=3,2 normal=0,-1,0\n"
    "sensor desk point position=3.2,3.1,0.8 normal=0,0,1\n"
    "render %s\n";

#endif
