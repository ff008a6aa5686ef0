# ctest: a terrain model ambler-gs cannot use ends a --screenshot launch
# with exit 1, the error on stderr and the window (error in its status
# line) saved, instead of waiting behind the error dialog; --startup-time
# and --measure-responsiveness likewise exit 1 with the error; a malformed
# --dtm-centre is refused with exit 2 before the window opens. The display
# is ctest's (scripts/test.sh runs it under xvfb-run), as for the widget
# tests.
set(dir ${WORK_DIR}/terrain-model-refusal)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
file(WRITE ${dir}/junk.tif "not a raster")
execute_process(COMMAND ${PROGRAM} --dtm ${dir}/junk.tif --screenshot ${dir}/shot.png
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 120)
if(NOT rc EQUAL 1 OR NOT err MATCHES "junk.tif: not a raster GDAL can read"
   OR NOT EXISTS ${dir}/shot.png)
  message(FATAL_ERROR "an unreadable terrain model: exit ${rc}, output '${out}${err}'")
endif()
foreach(option --startup-time --measure-responsiveness)
  execute_process(COMMAND ${PROGRAM} --dtm ${dir}/junk.tif ${option}
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 120)
  if(NOT rc EQUAL 1 OR NOT err MATCHES "junk.tif: not a raster GDAL can read")
    message(FATAL_ERROR "${option} on an unreadable terrain model: exit ${rc}, output '${out}${err}'")
  endif()
endforeach()
execute_process(COMMAND ${PROGRAM} --dtm ${dir}/junk.tif --dtm-centre 5x,3
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 60)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--dtm-centre must be EASTING,NORTHING")
  message(FATAL_ERROR "a malformed --dtm-centre: exit ${rc}, output '${out}${err}'")
endif()
message(STATUS "terrain model refused: exit 1 (window saved with --screenshot); bad --dtm-centre: exit 2")
