# Script half of vr_embed_csv and vr_embed_text (runs at build time with -P).
if(TEXT)
  file(READ "${SRC}" hex HEX)
  string(LENGTH "${hex}" hexlen)
  math(EXPR len "${hexlen} / 2")
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
  string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n" bytes "${bytes}")
  file(WRITE "${DST}.tmp"
    "/* Generated from ${SRC} by cmake/VrEmbedRun.cmake. Do not edit. */\n"
    "const unsigned char ${SYMBOL}[] = {\n${bytes}0x00};\n"
    "const unsigned long ${SYMBOL}_len = ${len};\n")
  file(RENAME "${DST}.tmp" "${DST}")
  return()
endif()
file(STRINGS "${SRC}" lines)
set(body "")
set(rows 0)
set(cols 0)
set(header_seen FALSE)
foreach(line IN LISTS lines)
  string(STRIP "${line}" line)
  if(line STREQUAL "" OR line MATCHES "^#")
    continue()
  endif()
  if(NOT header_seen)
    set(header_seen TRUE)
    continue()
  endif()
  string(REPLACE "," ";" fields "${line}")
  list(LENGTH fields n)
  if(cols EQUAL 0)
    set(cols ${n})
  elseif(NOT n EQUAL cols)
    message(FATAL_ERROR "${SRC}: row ${rows} has ${n} fields, expected ${cols}")
  endif()
  string(APPEND body "  ${line},\n")
  math(EXPR rows "${rows} + 1")
endforeach()
file(WRITE "${DST}.tmp"
  "/* Generated from ${SRC} by cmake/VrEmbedRun.cmake. Do not edit. */\n"
  "const double ${SYMBOL}[] = {\n${body}};\n"
  "const unsigned ${SYMBOL}_rows = ${rows};\n"
  "const unsigned ${SYMBOL}_cols = ${cols};\n")
file(RENAME "${DST}.tmp" "${DST}")
