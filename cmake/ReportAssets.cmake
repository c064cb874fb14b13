# The reports' plotting library: uPlot, pinned in package.json/package-lock.json at the
# top of the sources, installed by `npm ci` into the build tree (build/<preset>/npm/node_modules),
# and embedded into lathectl as a generated source (report_assets.cpp), so every report.html
# carries it inline and opens offline. The same `npm ci` brings MQTT.js's browser bundle for the
# live dashboard (dashboard/CMakeLists.txt). There is no fallback: without npm the configure step stops
# here; without the npm registry (or a filled npm cache) the build stops at `npm ci`.
find_program(LATHECTL_NPM npm)
if(NOT LATHECTL_NPM)
  message(FATAL_ERROR "npm not found: the reports' plotting library (uPlot) is installed with "
                      "`npm ci` from package-lock.json at build time. Install npm "
                      "(bash scripts/install-deps.sh) and configure again.")
endif()
set(LATHECTL_NPM_DIR ${PROJECT_BINARY_DIR}/npm)
configure_file(${PROJECT_SOURCE_DIR}/package.json ${LATHECTL_NPM_DIR}/package.json COPYONLY)
configure_file(${PROJECT_SOURCE_DIR}/package-lock.json ${LATHECTL_NPM_DIR}/package-lock.json COPYONLY)
set(_uplot ${LATHECTL_NPM_DIR}/node_modules/uplot)
set(_mqtt ${LATHECTL_NPM_DIR}/node_modules/mqtt)
add_custom_command(
  OUTPUT ${_uplot}/dist/uPlot.iife.min.js ${_uplot}/dist/uPlot.min.css ${_uplot}/LICENSE
         ${_mqtt}/dist/mqtt.min.js ${_mqtt}/LICENSE.md
  COMMAND ${CMAKE_COMMAND} -DNPM=${LATHECTL_NPM} -DDIR=${LATHECTL_NPM_DIR}
          -P ${PROJECT_SOURCE_DIR}/cmake/NpmCi.cmake
  DEPENDS ${LATHECTL_NPM_DIR}/package.json ${LATHECTL_NPM_DIR}/package-lock.json
          ${PROJECT_SOURCE_DIR}/cmake/NpmCi.cmake
  COMMENT "npm ci: uPlot for the reports' interactive plots, MQTT.js for the dashboard")
set(LATHECTL_REPORT_ASSETS_CPP ${PROJECT_BINARY_DIR}/generated/report_assets.cpp)
add_custom_command(
  OUTPUT ${LATHECTL_REPORT_ASSETS_CPP}
  COMMAND ${CMAKE_COMMAND} -DJS=${_uplot}/dist/uPlot.iife.min.js -DCSS=${_uplot}/dist/uPlot.min.css
          -DLICENSE=${_uplot}/LICENSE -DPAGE_JS=${PROJECT_SOURCE_DIR}/src/io/report_plot_script.js
          -DOUT=${LATHECTL_REPORT_ASSETS_CPP}
          -P ${PROJECT_SOURCE_DIR}/cmake/EmbedReportAssets.cmake
  DEPENDS ${_uplot}/dist/uPlot.iife.min.js ${_uplot}/dist/uPlot.min.css ${_uplot}/LICENSE
          ${PROJECT_SOURCE_DIR}/src/io/report_plot_script.js
          ${PROJECT_SOURCE_DIR}/cmake/EmbedReportAssets.cmake
  COMMENT "Embedding uPlot into lathectl (report_assets.cpp)")
