#!/usr/bin/env bash
# Command-line test: glTF metallic-roughness (docs/scene-format.md,
# "Materials"), on a real public file and the scene format:
#   - Khronos's ClearCoatTest.gltf (CC BY 4.0, Analytical Graphics, Ed
#     Mackey): 19 materials with metallic and roughness factors, one with a
#     metallicRoughnessTexture (RoughnessStripes.png) and no roughnessFactor
#     (glTF 2.0's default, 1), six with KHR_materials_clearcoat, one with
#     a see-through base colour texture, six with normal maps (two images).  One mesh
#     line renders them all; the notes say each material's factors, the
#     texture, and that clearcoat is not rendered; four textures load; the
#     striped texture changes the image against the same factors without
#     it, on every integrator;
#   (Khronos's BoxTextured.gltf, whose material gives no factors, takes
#   glTF's defaults, metallic 1 and roughness 1: test_vr_render_textures.sh);
#   - the pbr source in a scene, under the decomposition: the same image on
#     1 and 8 sub-domains;
#   - refusals (docs/bad-input.md): the model's metallic-roughness texture
#     missing, metallic= or roughness= missing or out of [0, 1], a missing
#     metallic_roughness= file.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
source "$(dirname "$0")/harness.sh"
data="$VR_SOURCE_DIR/tests/data"
cd "$tmp"

cp "$data"/models/khronos_clearcoat/* .
cat > cc.scn <<SCN
mesh ClearCoatTest.gltf
camera pinhole from=2.1,1.05,7 to=2.1,1.05,0 up=0,1,0 fov=20 resolution=48x32
light point position=-4,6,12 intensity=20000cd
sky overcast illuminance=3000
render integrator=path spp=8
SCN
"$bin" cc.scn -o cc --outputs exr 2> cc.err
check "ClearCoatTest.gltf renders from one mesh line" test $? -eq 0
check "a factor-only material is said with its factors" \
  grep -q "material 'Simple_Base' .*glTF metallic-roughness (metallic 0, roughness 0.44)" cc.err
check "the textured one with glTF's default roughness factor 1 and its texture" \
  grep -q "material 'RoughVariations_Coating' .*glTF metallic-roughness (metallic 0, roughness 1, times its metallic-roughness texture)" cc.err
check "KHR_materials_clearcoat is said not to be rendered, once for each of the six" \
  test "$(grep -c "its KHR_materials_clearcoat is not rendered" cc.err)" -eq 6
check "four textures load (base colour, metallic-roughness, two normal maps)" \
  grep -q "textures: 4 loaded" cc.err
# The same factors without the texture: the stripes make part of the
# coating smoother, so the image (framed on that pill) changes.
sed 's/^mesh ClearCoatTest.gltf$/material plain pbr color=#000000 metallic=0 roughness=1\nmesh ClearCoatTest.gltf material.RoughVariations_Coating=plain/' cc.scn > plain.scn
for integ in path bdpt photon progressive; do
  sed -i "s/integrator=[a-z]*/integrator=$integ/" cc.scn plain.scn
  "$bin" cc.scn -o cc_$integ --outputs exr 2> /dev/null
  ok=$?
  "$bin" plain.scn -o plain_$integ --outputs exr 2> /dev/null
  check "$integ: renders, and the metallic-roughness texture changes the image" \
    bash -c "test $ok -eq 0 && ! '$cmp' cc_$integ.exr plain_$integ.exr 5e-2 > /dev/null 2>&1"
done

cat > scene.scn <<SCN
material floor pbr color=#8a6a4a metallic=0 roughness=0.35
material brass pbr rgb=0.9,0.7,0.3 metallic=1 roughness=0.25
material coat pbr reflectance=0.2 metallic=0 roughness=0
rect center=0,0,0 normal=0,0,1 size=6,6 material=floor
box min=-1.6,-0.5,0 max=-0.6,0.5,1 material=brass
box min=0.6,-0.5,0 max=1.6,0.5,1 material=coat
camera pinhole from=0,-6,3 to=0,0,0.5 up=0,0,1 fov=40 resolution=40x30
light point position=2,-3,5 intensity=2000cd
render integrator=path spp=4
SCN
"$bin" scene.scn -o one --outputs exr 2> /dev/null
check "pbr materials render" test $? -eq 0
"$bin" scene.scn -o eight --subdomains 8 --outputs exr 2> /dev/null
check "the same image on 8 sub-domains" "$cmp" one.exr eight.exr 1e-6

rm RoughnessStripes.png
refuse render-mr-texture-missing "$bin" cc.scn -o gone
check "the refusal names the scene line" grep -q "cc.scn:1:1:" "$tmp/refused.err"
printf 'material m pbr color=#808080 roughness=0.5\nrect center=0,0,0 normal=0,0,1 size=1,1 material=m\n' > bad1.scn
refuse render-pbr-metallic-missing "$bin" bad1.scn -o bad1
printf 'material m pbr color=#808080 metallic=1.2 roughness=0.5\nrect center=0,0,0 normal=0,0,1 size=1,1 material=m\n' > bad2.scn
refuse render-pbr-metallic-range "$bin" bad2.scn -o bad2
printf 'material m pbr color=#808080 metallic=0 roughness=0.5 metallic_roughness=nosuch.png\nrect center=0,0,0 normal=0,0,1 size=1,1 material=m\n' > bad3.scn
refuse render-pbr-map-missing "$bin" bad3.scn -o bad3
printf 'material m lambert color=#808080 metallic=0\nrect center=0,0,0 normal=0,0,1 size=1,1 material=m\n' > bad4.scn
refuse render-lambert-metallic "$bin" bad4.scn -o bad4
finish
