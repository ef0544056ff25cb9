#!/usr/bin/env bash
# Command-line test: a model's own materials (docs/scene-format.md,
# "Materials from the model file"), on a real public file: tinyobjloader's
# Cornell box OBJ with its MTL (tests/data/models/cornell_tinyobj, MIT),
# nine objects over the materials white, red, green, blue and light with
# their Kd colours (blue names no face).
#   - one mesh line without material=: one object per file material with
#     faces (4), each unmapped one heard once on stderr with its colour;
#   - material.*=wall maps every group: no note, and the image is the one
#     of material=wall (the same triangles, split over 4 objects);
#   - material.red=grey maps one: the others still from the file;
#   - materials=FILE holds the maps in a file of their own ("* = wall" gives
#     the image of material=wall), its errors at the file's lines;
#   - an OBJ whose mtllib is commented out: its usemtl names are grey 0.5,
#     said to be defined nowhere (not Assimp's 0.6 passed off as theirs);
#   - Khronos's Box.gltf (CC BY 4.0) without material= takes its
#     baseColorFactor (0.8, 0, 0);
#   - Assimp's float-color.ply (MeshLab, vertex colours, no materials)
#     without material= renders its vertex colours, said once, the same
#     image on 8 sub-domains (the colours live in the cache's cells);
#     Assimp's cube.ply (no colours, no materials) is refused: the PLY
#     reader's white stand-in is not passed off as the file's;
#   - Crytek Sponza's chain material (verbatim MTL, its map_d mask) cuts
#     its quad out; without the mask's file the line is refused;
#   - units=mm up=y turn the file's millimetres, y up, into the scene's
#     metres, z up (the printed bounds, the scene's and the mesh line's own
#     with its triangle count, are the Cornell box's);
#   - refusals (docs/bad-input.md): a pattern that matches nothing lists
#     the file's materials, an unknown scene material, a file without
#     materials and no material=, bad colours, an unknown unit or up axis,
#     a format Assimp does not read (a Radiance .rad), with the list of
#     those it does.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
source "$(dirname "$0")/harness.sh"
cp "$VR_SOURCE_DIR"/tests/data/models/cornell_tinyobj/cornell_box.{obj,mtl} "$tmp/"
cd "$tmp"
scene() { # the mesh line's options, the output scene
  cat > "$2" <<SCN
material wall lambert reflectance=0.7
material grey lambert reflectance=0.3
mesh cornell_box.obj $1 scale=0.001
camera pinhole from=0.278,0.27,-0.8 to=0.278,0.27,0.28 up=0,1,0 fov=40 resolution=32x32
light point position=0.278,0.5,0.28 intensity=5cd
render integrator=path spp=4
SCN
}

scene "" own.scn
"$bin" own.scn -o own --outputs exr 2> own.err
check "renders a mesh without material= from its file's materials" test $? -eq 0
check "4 objects, one per file material with faces" grep -q "scene: 4 objects, 36 triangles" own.err
for m in white red green light; do
  check "material '$m' heard once" test "$(grep -c "material '$m' ([0-9]* triangles) is mapped to nothing" own.err)" -eq 1
done
check "the red wall's Kd (1 0 0) is said" grep -q "material 'red' (2 triangles) is mapped to nothing: its colour (linear 1, 0, 0)" own.err
check "blue, which names no face, is not" bash -c "! grep -q \"material 'blue'\" own.err"

scene "material.*=wall" all.scn
scene "material=wall" one.scn
"$bin" all.scn -o all --outputs exr 2> all.err && "$bin" one.scn -o one --outputs exr 2> /dev/null
check "material.*=wall and material=wall render" test $? -eq 0
check "every group mapped: no note" bash -c "! grep -q 'mapped to nothing' all.err"
check "material.*=wall gives the image of material=wall" "$cmp" all.exr one.exr 1e-6

# The same maps kept in a file (materials=FILE): one per line, comments.
printf '# the Cornell box, every group the wall\n\n*  =  wall\n' > all.map
scene "materials=all.map" mapped.scn
"$bin" mapped.scn -o mapped --outputs exr 2> mapped.err
check "materials=FILE renders" test $? -eq 0
check "materials=FILE gives the image of material=wall" "$cmp" mapped.exr one.exr 1e-6
printf 'white = wall\nmarble = grey\n' > bad.map
scene "materials=bad.map" mapbad1.scn
refuse render-mesh-mapfile-matches-nothing "$bin" mapbad1.scn -o mapbad1
check "the refusal names the map file's line" grep -q "bad.map:2:1: 'marble' matches no material" "$tmp/refused.err"
printf 'white = nosuch\n' > bad2.map
scene "materials=bad2.map" mapbad2.scn
refuse render-mesh-mapfile-unknown-material "$bin" mapbad2.scn -o mapbad2
check "an unknown material is named at the map file's line" grep -q "bad2.map:1:1: unknown material" "$tmp/refused.err"
printf 'white wall\n' > bad3.map
scene "materials=bad3.map" mapbad3.scn
refuse render-mesh-mapfile-malformed "$bin" mapbad3.scn -o mapbad3
scene "materials=nosuch.map" mapbad4.scn
refuse render-mesh-mapfile-missing "$bin" mapbad4.scn -o mapbad4

scene "material.red=grey material=wall" red.scn
"$bin" red.scn -o red --outputs exr 2> red.err
check "material.red= with material= for the rest" test $? -eq 0
check "no group falls back to the file" bash -c "! grep -q 'mapped to nothing' red.err"
check "and the image differs from all-wall" bash -c "! '$cmp' red.exr one.exr 1e-3 > /dev/null 2>&1"

scene "material.marble=wall" bad1.scn
refuse render-mesh-map-matches-nothing "$bin" bad1.scn -o bad1
check "the refusal names the line" grep -q "bad1.scn:3:" "$tmp/refused.err"
check "and writes nothing" test ! -e bad1.exr -a ! -e bad1.png
scene "material.red=nosuch" bad2.scn
refuse render-mesh-map-unknown-material "$bin" bad2.scn -o bad2
grep -v -E "^(mtllib|usemtl)" cornell_box.obj > plain.obj
sed 's/cornell_box.obj/plain.obj/' own.scn > bad3.scn
refuse render-mesh-no-materials "$bin" bad3.scn -o bad3
sed 's/^material grey .*/material grey lambert color=#80808g/' own.scn > bad4.scn
refuse render-colour-hex-bad "$bin" bad4.scn -o bad4
sed 's/^material grey .*/material grey lambert rgb=0.5,1.2,0.5/' own.scn > bad5.scn
refuse render-colour-out-of-range "$bin" bad5.scn -o bad5
# An OBJ whose usemtl names no .mtl defines (tinyobjloader's
# missing_material_file.obj, mtllib commented out): Assimp's stand-in grey
# must not pass for the file's colour.
cp "$VR_SOURCE_DIR"/tests/data/models/cornell_tinyobj/missing_material_file.obj "$tmp/"
sed 's/cornell_box.obj/missing_material_file.obj/' own.scn > miss.scn
"$bin" miss.scn -o miss --outputs exr 2> miss.err
check "an OBJ without its .mtl renders" test $? -eq 0
check "its red is said to be defined nowhere, grey 0.5" \
  grep -q "material 'red' (2 triangles) is mapped to nothing and has no colour (no newmtl .* defines it): grey 0.5" miss.err
check "no colour is claimed for it" bash -c "! grep -q 'its colour' miss.err"

# A glTF's base colour: Khronos's Box sample (tests/data/models/khronos_box,
# CC BY 4.0), one material with baseColorFactor [0.8, 0, 0, 1].
cp "$VR_SOURCE_DIR"/tests/data/models/khronos_box/Box.gltf "$tmp/"
cat > box.scn <<SCN
mesh Box.gltf
camera pinhole from=0,-3,0 to=0,0,0 fov=40 resolution=16x16
light point position=0,-3,2 intensity=5cd
render integrator=path spp=1
SCN
"$bin" box.scn -o box --outputs exr 2> box.err
check "a glTF without material= renders" test $? -eq 0
check "with its base colour (linear 0.8, 0, 0), said once" \
  test "$(grep -c "(12 triangles) is mapped to nothing: its colour (linear 0.8, 0, 0)" box.err)" -eq 1
check "the unit cube's bounds" grep -q "scene: bounds x -0.5 to 0.5, y -0.5 to 0.5, z -0.5 to 0.5" box.err
check "the mesh line's own triangles and bounds" \
  grep -q "scene: mesh 'Box.gltf' (line 1): 12 triangles in 1 object, bounds x -0.5 to 0.5, y -0.5 to 0.5, z -0.5 to 0.5 (m)" box.err

# Units and up axis: the Cornell data are millimetres with y up; turned to
# metres and z up, the room spans 0 to 0.556 in x, -0.5592 to 0 in y (its
# depth, 559.2 mm, along -y) and 0 to 0.5488 in z (its height, 548.8 mm):
# the published Cornell box dimensions.
scene "units=mm up=y" frame.scn
sed -i 's/ scale=0.001//' frame.scn
"$bin" frame.scn -o frame --outputs exr 2> frame.err
check "units=mm up=y render" test $? -eq 0
check "the bounds say metres, z up" grep -q "scene: bounds x 0 to 0.556, y -0.5592 to 0, z 0 to 0.5488" frame.err
check "and the mesh line its 36 triangles over its 4 file materials" \
  grep -q "scene: mesh 'cornell_box.obj' (line 3): 36 triangles in 4 objects, bounds x 0 to 0.556, y -0.5592 to 0, z 0 to 0.5488 (m)" frame.err
sed 's/units=mm up=y/units=yd/' frame.scn > bad6.scn
refuse render-mesh-units-unknown "$bin" bad6.scn -o bad6
sed 's/units=mm up=y/up=x/' frame.scn > bad7.scn
refuse render-mesh-up-unknown "$bin" bad7.scn -o bad7
printf 'not a SketchUp model\n' > room.skp
sed 's/cornell_box.obj units=mm up=y/room.skp material=wall/' frame.scn > bad8.scn
refuse render-mesh-format-unknown "$bin" bad8.scn -o bad8
check "the list names obj, gltf and fbx" grep -q "obj .*fbx.*gltf" "$tmp/refused.err"

cp "$VR_SOURCE_DIR"/tests/data/models/assimp_ply/*.ply "$tmp/"
cat > ply.scn <<SCN
material white lambert reflectance=1
mesh float-color.ply
camera pinhole from=100,66,300 to=100,66,0 up=0,1,0 fov=60 resolution=24x24
light point position=100,66,1000 intensity=1e7cd
render integrator=path spp=2
SCN
"$bin" ply.scn -o ply --outputs exr 2> ply.err
check "a PLY file's vertex colours render" test $? -eq 0
check "said once" test "$(grep -c "mesh 'float-color.ply' has no materials of its own: its vertex colours as spectra" ply.err)" -eq 1
"$bin" ply.scn -o ply8 --subdomains 8 --outputs exr 2> /dev/null
check "the same image on 8 sub-domains" "$cmp" ply.exr ply8.exr 1e-9
sed 's/^mesh float-color.ply$/mesh float-color.ply material=white/' ply.scn > plyw.scn
"$bin" plyw.scn -o plyw --outputs exr 2> /dev/null
check "material= on the line leaves the colours out (the image differs)" \
  bash -c "! '$cmp' ply.exr plyw.exr 1e-2 > /dev/null 2>&1"
sed 's/^mesh float-color.ply$/mesh cube.ply/' ply.scn > bad9.scn
refuse render-mesh-no-materials "$bin" bad9.scn -o bad9

# Crytek Sponza's chain material cuts its quad out by its map_d; without
# the mask's file the line is refused, naming it.
mkdir chain && cp -r "$VR_SOURCE_DIR"/tests/data/models/sponza_chain/* chain/
cat > chain/chain.scn <<SCN
mesh chain.obj
camera pinhole from=0,-5,0 to=0,0,0 up=0,0,1 fov=4 resolution=8x32
light point position=0,-5,0 intensity=100cd
render integrator=path spp=1
SCN
"$bin" chain/chain.scn -o chain/c --outputs exr 2> chain.err
check "Sponza's chain renders, cut out by its map_d" \
  grep -q "material 'chain' .*cut out where its map_d is below 0.5" chain.err
rm chain/textures/chain_texture_mask.png
refuse render-map-d-missing "$bin" chain/chain.scn -o chain/d
finish
