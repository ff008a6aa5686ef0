# ctest: ambler-gs without a display answers --help and --version, and
# refuses to start with exit code 2 and a message saying what to do,
# rather than Qt's abort.
set(no_display env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM)
foreach(option --help --version)
  execute_process(COMMAND ${no_display} ${PROGRAM} ${option}
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "ambler-gs")
    message(FATAL_ERROR "${option} without a display: exit ${rc}, output '${out}${err}'")
  endif()
endforeach()
execute_process(COMMAND ${no_display} ${PROGRAM} --seed 3
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 30)
if(NOT rc EQUAL 2 OR NOT err MATCHES "no display.*xvfb-run")
  message(FATAL_ERROR "a start without a display: exit ${rc}, output '${out}${err}'")
endif()
message(STATUS "without a display: help, version, and a refusal with exit 2")
