# The sample office's context ground (context_e3bb11d6_0, reflectance 0.5)
# lies in the plane of the room's floor (0.2, z = 0); this prints the
# envelope with that one polygon lowered to z = -0.01, so that the two no
# longer coincide under the room (used by bench/bench_radiance_office.sh
# and tests/cli/test_vr_render_rad.sh for both renderers).
# Paragraph mode: a record is a primitive; words 7.. are its coordinates.
BEGIN { RS = ""; ORS = "\n\n" }
/context_e3bb11d6_0/ {
  n = split($0, w, /[ \n]+/)
  out = w[1] " " w[2] " " w[3] "\n0\n0\n12"
  for (k = 7; k <= n; k++) out = out " " (((k - 7) % 3 == 2) ? "-0.01" : w[k])
  print out
  next
}
{ print }
