# cmake -DNPM=npm -DDIR=<dir with package.json + package-lock.json> -P NpmCi.cmake
# Runs `npm ci` there; on failure, one message that says what it needed.
execute_process(COMMAND ${NPM} ci --no-audit --no-fund --ignore-scripts --loglevel=error
                WORKING_DIRECTORY ${DIR} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "`npm ci` in ${DIR} failed (exit ${rc}): the reports' plotting library "
                      "(uPlot) and the dashboard's MQTT.js (package-lock.json) could not be installed; it needs the npm "
                      "registry or an npm cache that holds it.")
endif()
