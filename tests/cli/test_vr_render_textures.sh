#!/usr/bin/env bash
# Command-line test: textures (docs/scene-format.md, "Textures"), on real
# public files:
#   - Khronos's BoxTextured.gltf (CC BY 4.0): its base colour texture is a
#     PNG embedded as a data: URI; rendered from one mesh line, the texture
#     said once, and the image differs from the same box in plain grey;
#   - tinyobjloader's issue-92.obj: "map_Kd tmp.png " (a trailing blank)
#     with a real PNG beside it (GDAL's icon from tests/data/images) renders
#     it; without the PNG the line is refused, naming the texture;
#   - tinyobjloader's texture-filename-with-whitespace.obj: "map_Kd
#     texture 01.png" (a blank inside the name) is found;
#   - lambert texture= with a real camera JPEG (Nikon D2H, goexif) renders,
#     and tile=, colorspace=linear change the image;
#   - the pipeline: vr-rgb2spec --per-pixel --texture (the sample photos)
#     into a fresh database, then db:NAME renders per texel; the texture
#     file changed afterwards (a byte appended) is refused by its SHA-256;
#   - the decomposition: a room of textured boxes, a tiled floor and a
#     cut-out (alpha) screen renders the same image on 1 sub-domain, on 8
#     under a memory budget (textures counted in it) and on 2 MPI ranks;
#   - refusals (docs/bad-input.md): a missing texture, a folder, a file
#     that is not an image, a truncated PNG, options without texture=, a
#     bad cutoff or tile, texture= on a database material other than none,
#     normal_scale= without normal_map=, a missing normal map.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
source "$(dirname "$0")/harness.sh"
data="$VR_SOURCE_DIR/tests/data"
cd "$tmp"

cp "$data"/models/khronos_box_textured/BoxTextured.gltf .
cat > box.scn <<SCN
mesh BoxTextured.gltf
camera pinhole from=2.2,-2.6,1.8 to=0,0,0 up=0,0,1 fov=35 resolution=48x48
light point position=3,-2,4 intensity=600cd
render integrator=path spp=4
SCN
"$bin" box.scn -o box --outputs exr 2> box.err
check "a glTF with an embedded base colour texture renders" test $? -eq 0
check "its texture is said once" test "$(grep -c "its texture '\*0' as spectra" box.err)" -eq 1
check "the textures line counts it" grep -q "textures: 1 loaded" box.err
check "its glTF metallic-roughness is glTF 2.0's default (metallic 1, roughness 1)" \
  grep -q "glTF metallic-roughness (metallic 1, roughness 1)" box.err
sed 's/^mesh BoxTextured.gltf$/material grey lambert reflectance=0.5\nmesh BoxTextured.gltf material=grey/' box.scn > grey.scn
"$bin" grey.scn -o grey --outputs exr 2> /dev/null
check "the textured box differs from a grey one" bash -c "! '$cmp' box.exr grey.exr 1e-2 > /dev/null 2>&1"

cp "$data"/models/tinyobj_textures/issue-92.{obj,mtl} .
cat > obj.scn <<SCN
mesh issue-92.obj
camera pinhole from=0,-12,0 to=1,0,0 up=0,0,1 fov=60 resolution=16x16
light point position=0,-12,0 intensity=600cd
render integrator=path spp=1
SCN
refuse render-texture-model-missing "$bin" obj.scn -o obj
check "the refusal names the scene line" grep -q "obj.scn:1:1:" "$tmp/refused.err"
cp "$data"/images/gdalicon.png tmp.png
"$bin" obj.scn -o obj --outputs exr 2> obj.err
check "map_Kd with a trailing blank finds tmp.png" test $? -eq 0 -a -n "$(grep "its texture 'tmp.png' as spectra" obj.err)"

cp "$data"/models/tinyobj_textures/texture-filename-with-whitespace.{obj,mtl} .
cp "$data"/images/gdalicon.png "texture 01.png"
sed 's/issue-92.obj/texture-filename-with-whitespace.obj/' obj.scn > ws.scn
"$bin" ws.scn -o ws --outputs exr 2> ws.err
check "a blank inside the texture's name is kept" test $? -eq 0 -a -n "$(grep "its texture 'texture 01.png' as spectra" ws.err)"

cp "$data"/images/nikon_d2h_goexif.jpg photo.jpg
cp "$data"/images/cmake_smalllogo_grey_alpha.png logo.png
cat > room.scn <<SCN
material floor lambert texture=photo.jpg tile=4
material screen lambert texture=logo.png alpha=mask
material wall lambert reflectance=0.6
rect center=0,0,0 normal=0,0,1 size=6,6 material=floor
rect center=0,3,1.5 normal=0,-1,0 size=6,3 material=wall
rect center=0,0.5,1 normal=0,-1,0 size=1.2,1.2 up=0,0,1 material=screen
mesh BoxTextured.gltf translate=-1.5,1,0.5
mesh BoxTextured.gltf translate=1.5,1.5,0.5
mesh BoxTextured.gltf translate=0,2.2,0.5 scale=0.6
camera pinhole from=0,-4,2 to=0,1,0.8 up=0,0,1 fov=60 resolution=48x36
light point position=0,-1,2.8 intensity=300cd
render integrator=path spp=4 depth=3
SCN
"$bin" room.scn -o room1 --outputs exr --subdomains 1 2> room1.err
check "a textured room renders on one sub-domain" test $? -eq 0
"$bin" room.scn -o room8 --outputs exr --subdomains 8 --memory-budget 24M --threads 2 > room8.out 2> room8.err
check "on 8 sub-domains under a 24 MiB budget" test $? -eq 0
check "the same image" "$cmp" room1.exr room8.exr 1e-6
if [ "${VR_HAVE_MPI:-OFF}" = "ON" ]; then
  mpi=(mpirun --oversubscribe -np 2)
  [ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
  # As in test_vr_render_mpi.sh: under the sanitizer build the ranks keep
  # AddressSanitizer's checks but not its leak report (Open MPI's own
  # blocks, kept until exit, cannot be told from ours by name).
  if [ -n "${ASAN_OPTIONS:-}" ]; then
    mpi+=(-x "ASAN_OPTIONS=$ASAN_OPTIONS:detect_leaks=0")
  fi
  [ -n "${UBSAN_OPTIONS:-}" ] && mpi+=(-x UBSAN_OPTIONS)
  "${mpi[@]}" "$bin" room.scn -o roomr --outputs exr --subdomains 8 --threads 1 > /dev/null 2> roomr.err
  check "on 2 MPI ranks" test $? -eq 0
  check "the same image on ranks" "$cmp" room1.exr roomr.exr 1e-6
fi
"$bin" room.scn -o roomt --outputs exr --subdomains 8 --memory-budget 2M 2> roomt.err
check "a budget the textures and film fill is refused with the figure" \
  test $? -ne 0 -a -n "$(grep "textures, photon and state maps" roomt.err)"
plane() { # material options, output scene
  cat > "$2" <<SCN
material m lambert $1
rect center=0,0,0 normal=0,-1,0 size=1.6,1.2 up=0,0,1 material=m
camera pinhole from=0,-5,0 to=0,0,0 up=0,0,1 fov=18.2 resolution=40x30
light point position=0,-100,0 intensity=1e6cd
render integrator=path spp=2
SCN
}
plane "texture=photo.jpg" jpg.scn
"$bin" jpg.scn -o jpg --outputs exr 2> jpg.err
check "a camera JPEG as a texture renders" test $? -eq 0
plane "texture=photo.jpg tile=2" tile.scn
"$bin" tile.scn -o tile --outputs exr 2> /dev/null
check "tile=2 changes the image" bash -c "! '$cmp' jpg.exr tile.exr 1e-2 > /dev/null 2>&1"
plane "texture=photo.jpg colorspace=linear" lin.scn
"$bin" lin.scn -o lin --outputs exr 2> /dev/null
check "colorspace=linear changes the image" bash -c "! '$cmp' jpg.exr lin.exr 1e-2 > /dev/null 2>&1"

plane "texture=nosuch.png" bad1.scn
refuse render-texture-missing "$bin" bad1.scn -o bad1
check "the refusal names line and column" grep -q "bad1.scn:1:20:" "$tmp/refused.err"
check "and writes nothing" test ! -e bad1.exr -a ! -e bad1.png
mkdir adir
plane "texture=adir" bad2.scn
refuse render-texture-folder "$bin" bad2.scn -o bad2
printf 'not a picture\n' > fake.png
plane "texture=fake.png" bad3.scn
refuse render-texture-not-image "$bin" bad3.scn -o bad3
check "the refusal names the material's line and the file" grep -q "bad3.scn:1:1: material 'm': .*fake.png" "$tmp/refused.err"
head -c 1000 "$data"/images/gdalicon.png > cut.png
plane "texture=cut.png" bad4.scn
refuse render-texture-truncated "$bin" bad4.scn -o bad4
plane "reflectance=0.5 colorspace=linear" bad5.scn
refuse render-texture-option-alone "$bin" bad5.scn -o bad5
plane "texture=photo.jpg alpha=blend alpha_cutoff=0.3" bad6.scn
refuse render-texture-cutoff-without-mask "$bin" bad6.scn -o bad6
plane "texture=photo.jpg tile=0" bad7.scn
refuse render-texture-tile "$bin" bad7.scn -o bad7
sed 's/^material m lambert .*/material m db:anything texture=photo.jpg/' jpg.scn > bad8.scn
refuse render-texture-db-option "$bin" bad8.scn -o bad8
plane "reflectance=0.5 normal_scale=2" bad9.scn
refuse render-normal-scale-alone "$bin" bad9.scn -o bad9
plane "reflectance=0.5 normal_map=nosuch_n.png" bad10.scn
refuse render-normal-map-missing "$bin" bad10.scn -o bad10

export VR_MATDB="$tmp/m.db"
ph="$VR_SOURCE_DIR/samples/photos"
"$VR_RGB2SPEC" "$ph"/d65.png "$ph"/a.png "$ph"/led.png "$ph"/f11.png --per-pixel "$tmp/tex.exr" \
  --texture photo-tex > /dev/null 2>&1
check "vr-rgb2spec saves a spectral texture" test $? -eq 0
sed 's/^material m lambert .*/material m db:photo-tex/' jpg.scn > spec.scn
"$bin" spec.scn -o spec --outputs exr 2> spec.err
check "db:NAME of a spectral texture renders" test $? -eq 0 -a -n "$(grep "textures: 1 loaded" spec.err)"
printf 'x' >> "$tmp/tex.exr"
refuse render-texture-changed "$bin" spec.scn -o spec2
check "the refusal names the scene line and the file" grep -q "spec.scn:1:1: material 'm': .*tex.exr" "$tmp/refused.err"
sed 's/^material m db:photo-tex$/material m db:photo-tex texture=none/' spec.scn > none.scn
"$bin" none.scn -o none --outputs exr 2> /dev/null
check "texture=none renders the mean spectrum without reading the file" test $? -eq 0
finish
