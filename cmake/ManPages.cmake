# Man pages, installed gzip-compressed (gzip -9n: no name or time stamp, reproducible) where man
# finds them: share/man/man<section>/<page>.<section>.gz.
find_program(LATHECTL_GZIP gzip REQUIRED)
function(lathectl_man_page source component)
  get_filename_component(page ${source} NAME)
  string(REGEX REPLACE "^.*\\.([0-9])$" "\\1" section ${page})
  set(out ${PROJECT_BINARY_DIR}/man/${page}.gz)
  add_custom_command(OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
    COMMAND ${LATHECTL_GZIP} -9nc ${source} > ${out}
    DEPENDS ${source} VERBATIM)
  add_custom_target(man_${page} ALL DEPENDS ${out})
  install(FILES ${out} DESTINATION ${CMAKE_INSTALL_MANDIR}/man${section} COMPONENT ${component})
endfunction()

lathectl_man_page(${PROJECT_SOURCE_DIR}/man/lathectl.1 lathectl)
