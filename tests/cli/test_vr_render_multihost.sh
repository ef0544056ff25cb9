#!/usr/bin/env bash
# Command-line test of vr-render on two "hosts" of one machine: each rank in
# its own network namespace, joined to the others by a veth pair and a
# bridge, with a rate limit (and a delay, where the kernel has netem) on
# each link; Open MPI over TCP only (no shared memory between the ranks),
# started in the namespaces by a launcher agent as ssh would start it on
# other machines; each host with its own geometry cache folder, built by
# that host.  The image must be one process's (1e-6 relative per value),
# rays created = finished, and rays must have crossed the links.
#
# Needs root (network namespaces, a bridge, mounts): elsewhere it reports
# itself skipped (exit 77, which CTest shows as "Skipped").
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

skip() { echo "# SKIP: $*"; exit 77; }
[ "$VR_HAVE_MPI" = "ON" ] || skip "built without MPI"
# Built with MPI, mpirun is installed by the set-up: its absence fails.
command -v mpirun > /dev/null || { echo "not ok - mpirun is missing (scripts/install-deps.sh)"; exit 1; }
[ "$(id -u)" -eq 0 ] || skip "needs root for network namespaces"
command -v ip > /dev/null && command -v tc > /dev/null || skip "needs iproute2 (ip, tc)"

# Names unique to this run (interface names are at most 15 bytes).
tag=$(( $$ % 100000 ))
net=10.$(( 100 + $$ % 100 )).$(( RANDOM % 250 + 1 ))
br=vrb$tag
hosts=(vrh${tag}a vrh${tag}b)
cleanup() {
  for i in 0 1; do ip link del "vrv$tag$i" 2>/dev/null; ip netns del "${hosts[$i]}" 2>/dev/null; done
  ip link del "$br" 2>/dev/null
  kill $(jobs -p) 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT

ip link add "$br" type bridge 2> "$tmp/net.err" || skip "cannot make a bridge: $(cat "$tmp/net.err")"
ip addr add "$net.1/24" dev "$br" && ip link set "$br" up
link="rate limit 1 Gbit/s"
for i in 0 1; do
  ns=${hosts[$i]}
  ip netns add "$ns" || skip "cannot make a network namespace"
  ip link add "vrv$tag$i" type veth peer name eth0 netns "$ns"
  ip link set "vrv$tag$i" master "$br" up
  ip -n "$ns" addr add "$net.$((i + 2))/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$ns" link set lo up
  # netem gives the delay and the rate; kernels without it (no sch_netem)
  # get the rate from a token bucket.
  if tc -n "$ns" qdisc add dev eth0 root netem delay 2ms rate 1gbit 2> /dev/null; then
    link="delay 2 ms, rate limit 1 Gbit/s (netem)"
  else
    tc -n "$ns" qdisc add dev eth0 root tbf rate 1gbit burst 64kb latency 50ms
  fi
done
echo "# two hosts in network namespaces ${hosts[*]} on $net.0/24: $link"

# The launcher agent, in ssh's place: "agent [options] HOST COMMAND...".
# It enters HOST's namespace (ip netns exec gives it a mount namespace of
# its own too) and binds that host's cache folder over the shared path, so
# each host reads only the cache it built.  Each host's Open MPI daemon
# gets its own TMPDIR, as a real host has its own /tmp: the two daemons
# had raced creating one session folder tree ("mkdir ... File exists",
# orte_init failed) in two of this session's full ctest runs.
cat > "$tmp/agent.sh" <<AGENT
#!/bin/sh
while [ \$# -gt 0 ]; do case "\$1" in -*) shift;; *) break;; esac; done
host=\$1; shift
case "\$host" in
  $net.2) ns=${hosts[0]};;
  $net.3) ns=${hosts[1]};;
  *) echo "agent: unknown host \$host" >&2; exit 1;;
esac
echo "\$ns" >> "$tmp/launched"
mkdir -p "$tmp/cache-\$ns" "$tmp/tmp-\$ns"
exec ip netns exec "\$ns" /bin/sh -c "mount --bind '$tmp/cache-\$ns' '$tmp/cache' && export TMPDIR='$tmp/tmp-\$ns' && exec \$*"
AGENT
chmod +x "$tmp/agent.sh"
printf '%s slots=1\n%s slots=1\n' "$net.2" "$net.3" > "$tmp/hosts"
mkdir -p "$tmp/cache"

source "$(dirname "$0")/mpi_room.sh"  # $tmp/room.scn

# The reference: one process, the whole scene in one cell, its own cache.
(cd "$tmp" && "$bin" room.scn --subdomains 1 --threads 1 --cache "$tmp/cache-one" -o one --quiet)
check "one process renders" test $? -eq 0

# rtc_hwloc_vmhole none: the daemon started in the second namespace
# otherwise maps hwloc's shared topology into the "biggest" hole of its
# address space and crashed there (a segmentation fault in
# hwloc_shmem_topology_write) in some runs; the ranks gain nothing from
# sharing it.
mpi=(mpirun --allow-run-as-root --hostfile "$tmp/hosts" -np 2 -x VR_MATDB
     --mca plm_rsh_agent "$tmp/agent.sh" --mca btl tcp,self
     --mca btl_tcp_if_include "$net.0/24" --mca oob_tcp_if_include "$net.0/24"
     --mca rtc_hwloc_vmhole none)
if [ -n "${ASAN_OPTIONS:-}" ]; then
  export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
  mpi+=(-x ASAN_OPTIONS)
fi
(cd "$tmp" && timeout 300 "${mpi[@]}" "$bin" room.scn --subdomains 8 --threads 1 --cache "$tmp/cache" \
   -o two --stats two.json --quiet) > "$tmp/two.out" 2>&1
rc=$?
check "2 ranks on 2 namespaced hosts over TCP render" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/two.out" | head -20
check "each rank was started in its own host's namespace" \
  test "$(sort -u "$tmp/launched" 2>/dev/null | wc -l)" -eq 2
"$cmp" "$tmp/one.exr" "$tmp/two.exr" > "$tmp/cmp.txt"; rc=$?
check "2 hosts: the image of one process" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/cmp.txt"
python3 - "$tmp/two.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["rays"]["created"] == s["rays"]["finished"], s["rays"]
r = s["ranks"]
assert len(r) == 2, r
sent = sum(x["rays_sent"] for x in r)
recv = sum(x["rays_received"] for x in r)
# rays crossed the links, and every one sent arrived
assert sent == recv and sent > 0, (sent, recv)
print("# rays sent over TCP:", sent, "bytes:", sum(x["bytes_sent"] for x in r), file=sys.stderr)
PY
check "2 hosts: rays created = finished, rays crossed the links and all arrived" test $? -eq 0
# Each host built its own cache (the cells it loaded) and nothing was
# written to the shared path itself.
n0=$(find "$tmp/cache-${hosts[0]}" -name 'cell-*.vrc' | wc -l)
n1=$(find "$tmp/cache-${hosts[1]}" -name 'cell-*.vrc' | wc -l)
check "each host has its own cache ($n0 and $n1 cell files)" test "$n0" -gt 0 -a "$n1" -gt 0
check "nothing was written to the path the hosts share" test -z "$(ls -A "$tmp/cache")"
finish
