#!/usr/bin/env bash
# Command-line test: inputs that are not regular text files are refused by
# what they are (issue 35, class 5; docs/bad-input.md, "Every tool: inputs
# that are not regular text files"):
#   - a .csv that is a symbolic link to /dev/zero (read without bound
#     before: gigabytes in seconds) is a character device;
#   - a folder given as a file is a folder (before: "read error", "model
#     file larger than 64 KiB", "unknown material");
#   - a named pipe (FIFO) is refused without opening it (an open would wait
#     for a writer);
#   - UTF-16 text, as `iconv -t UTF-16` and spreadsheets' "Unicode text"
#     write it (a byte-order mark, then two bytes a character), is named as
#     such with what to do (before: "binary data (NUL byte)").
# Each refusal is quick: every command runs under a 20 s timeout, which
# only a read without bound or a blocked open would reach.
set -u
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
s="$src/samples"
cd "$tmp"
ln -s /dev/zero zero.csv
mkdir adir
mkfifo fifo.csv
iconv -f UTF-8 -t UTF-16 "$s/spectra/colorchecker_babelcolor.csv" > u16.csv
iconv -f UTF-8 -t UTF-16 "$s/ellipsometry/thermal_oxide.csv" > e16.csv
t() { timeout 20 "$@"; }
export -f t

refuse input-device bash -c 't "$@"' _ "$VR_MATDB_TOOL" import zero.csv
refuse input-folder bash -c 't "$@"' _ "$VR_COLOUR" adir
refuse input-fifo bash -c 't "$@"' _ "$VR_COLOUR" fifo.csv
refuse input-utf16 bash -c 't "$@"' _ "$VR_COLOUR" u16.csv
refuse input-utf16 bash -c 't "$@"' _ "$VR_MATDB_TOOL" import u16.csv
refuse input-utf16 bash -c 't "$@"' _ "$VR_ELLIPSO" fit e16.csv
refuse input-folder bash -c 't "$@"' _ "$VR_ELLIPSO" fit adir
refuse input-folder bash -c 't "$@"' _ "$VR_ELLIPSO" fit "$s/ellipsometry/thermal_oxide.csv" --model adir
refuse input-folder bash -c 't "$@"' _ "$VR_SPECTRO" metrics adir
refuse input-folder bash -c 't "$@"' _ "$VR_RENDER" adir
refuse input-fifo bash -c 't "$@"' _ "$VR_RENDER" fifo.csv
check "the database was not filled by any of them" \
  bash -c '! "$1" list 2> /dev/null | grep -q "^zero\|^u16"' _ "$VR_MATDB_TOOL"
finish
