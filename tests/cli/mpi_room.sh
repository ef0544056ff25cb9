# Shared by the MPI command-line tests (sourced after harness.sh, with $src
# set): writes $tmp/room.scn, a room with the sample meshes, a mirror, a
# point light and a window-like emitter, path tracing with four sensor
# points; small enough for a test, with paths that cross many cells.
cat > "$tmp/room.scn" <<SCN
camera pinhole from=2.5,1.6,1.5 to=2.5,-2,1.0 fov=80 resolution=48x32
material wall lambert reflectance=0.6
material red lambert reflectance=0.3
material mirror db:Ag
material lamp black
box min=0,-2,0 max=5,2,2.7 material=wall
mesh $src/samples/meshes/bed.obj material=red rotate=0,0,1,90 translate=1.05,-0.45,0
mesh $src/samples/meshes/lamp.obj material=mirror translate=4.3,-1.3,0.75
mesh $src/samples/meshes/table.ply material=red rotate=0,0,1,90 translate=4.3,-0.9,0
rect center=0.02,0,1.3 normal=1,0,0 size=1.5,1 material=mirror
rect center=2.5,-1.97,1.5 normal=0,1,0 size=1.5,1 material=lamp emission=2000cd/m2
light point position=2.5,0,2.4 intensity=200cd
sensor floor grid origin=1,-1.5,0.01 u=3,0,0 v=0,3,0 n=2,2 normal=0,0,1
render integrator=path spp=4 depth=6 seed=3 sensor_samples=256
SCN
