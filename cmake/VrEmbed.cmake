# Turns a numeric CSV data table (comment lines start with '#', one header
# line, then rows of numbers) into a C source holding one flat array, so that
# the published tables ship inside the libraries and need no install path.
#
#   vr_embed_csv(OUT_VAR SYMBOL CSV_FILE)
# defines   const double SYMBOL[];   const unsigned SYMBOL_rows, SYMBOL_cols;
function(vr_embed_csv out_var symbol csv)
  set(src "${CMAKE_CURRENT_SOURCE_DIR}/${csv}")
  set(dst "${CMAKE_CURRENT_BINARY_DIR}/embedded/${symbol}.c")
  add_custom_command(
    OUTPUT "${dst}"
    COMMAND ${CMAKE_COMMAND} -DSRC=${src} -DDST=${dst} -DSYMBOL=${symbol}
            -P "${PROJECT_SOURCE_DIR}/cmake/VrEmbedRun.cmake"
    DEPENDS "${src}" "${PROJECT_SOURCE_DIR}/cmake/VrEmbedRun.cmake"
    COMMENT "Embedding ${csv}")
  set(${out_var} ${${out_var}} "${dst}" PARENT_SCOPE)
endfunction()

# Embeds a text file verbatim as   const unsigned char SYMBOL[];  const unsigned long SYMBOL_len;
function(vr_embed_text out_var symbol file)
  set(src "${CMAKE_CURRENT_SOURCE_DIR}/${file}")
  set(dst "${CMAKE_CURRENT_BINARY_DIR}/embedded/${symbol}.c")
  add_custom_command(
    OUTPUT "${dst}"
    COMMAND ${CMAKE_COMMAND} -DSRC=${src} -DDST=${dst} -DSYMBOL=${symbol} -DTEXT=1
            -P "${PROJECT_SOURCE_DIR}/cmake/VrEmbedRun.cmake"
    DEPENDS "${src}" "${PROJECT_SOURCE_DIR}/cmake/VrEmbedRun.cmake"
    COMMENT "Embedding ${file}")
  set(${out_var} ${${out_var}} "${dst}" PARENT_SCOPE)
endfunction()
