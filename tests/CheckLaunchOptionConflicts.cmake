# ctest: ambler-gs refuses, with exit 2 and the reason, launch options of
# which one would wait for what the other never shows (a soak or a
# measurement behind a replay would wait forever) or quit before it, or
# that name a ground it does not have; each pair below is one such.
set(pairs
    "--soak 3 --dtm x.tif|--soak walks courses 1-10 by itself: it takes no --dtm"
    "--soak 3 --replay x.db|--soak walks courses 1-10 by itself: it takes no --replay"
    "--soak 3 --family rocks|--soak walks courses 1-10 by itself: it takes no --family"
    "--dtm x.tif --family rocks|--dtm simulates on the terrain model: it takes no --family"
    "--family moon|--family must be course, rocks, craters, rough, negative or slope"
    "--replay x.db --measure-responsiveness|--replay shows the log alone: it takes no --measure-responsiveness"
    "--replay x.db --startup-time|--replay shows the log alone: it takes no --startup-time"
    "--startup-time --screenshot x.png|--startup-time quits at the first scan: it takes no --screenshot")
foreach(pair ${pairs})
  string(FIND "${pair}" "|" bar)
  string(SUBSTRING "${pair}" 0 ${bar} command)
  math(EXPR bar "${bar} + 1")
  string(SUBSTRING "${pair}" ${bar} -1 expected)
  separate_arguments(args UNIX_COMMAND "${command}")
  execute_process(COMMAND ${PROGRAM} ${args}
                  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 60)
  string(FIND "${err}" "${expected}" at)
  if(NOT rc EQUAL 2 OR at EQUAL -1)
    message(FATAL_ERROR "ambler-gs ${command}: exit ${rc}, output '${out}${err}'")
  endif()
endforeach()
message(STATUS "conflicting launch options refused with exit 2 and the reason")
