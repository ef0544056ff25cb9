# Sourced by tests/cli/test_vr_render_annual.sh and bench/bench_annual.sh:
# "room_shell" prints the scene lines of a closed 4 x 4 x 3 m room whose
# south wall (y = 0) has a 2 x 1.2 m opening at x 1..3, z 0.9..2.1 (the
# shell of tests/render/daylit_room.h), walls of reflectance 0.5.
room_shell() {
  cat <<'EOS'
material wall lambert reflectance=0.5
rect center=2,2,0   normal=0,0,1  size=4,4 material=wall
rect center=2,2,3   normal=0,0,-1 size=4,4 material=wall
rect center=2,4,1.5 normal=0,-1,0 size=4,3 material=wall
rect center=0,2,1.5 normal=1,0,0  size=4,3 material=wall
rect center=4,2,1.5 normal=-1,0,0 size=4,3 material=wall
rect center=2,0,0.45 normal=0,1,0 size=4,0.9 material=wall
rect center=2,0,2.55 normal=0,1,0 size=4,0.9 material=wall
rect center=0.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall
rect center=3.5,0,1.5 normal=0,1,0 size=1,1.2 material=wall
EOS
}
