# cmake -DEXE=path/to/brushtrace -DOUT=file -P help_text.cmake
# Writes the --help of brushtrace and of each of its commands into one text file (installed as
# share/doc/brushtrace/brushtrace-help.txt), taken from the executable so that it is CLI11's
# own text and cannot drift from the options. The commands are read from the top-level help.
execute_process(COMMAND ${EXE} --help OUTPUT_VARIABLE top RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${EXE} --help failed (${rc})")
endif()
string(FIND "${top}" "Subcommands:" at)
if(at EQUAL -1)
  string(FIND "${top}" "SUBCOMMANDS:" at)
endif()
string(SUBSTRING "${top}" ${at} -1 listing)
string(REGEX MATCHALL "\n  [a-z][a-z0-9-]*" names "${listing}")
set(text "${top}")
foreach(name ${names})
  string(STRIP "${name}" name)
  execute_process(COMMAND ${EXE} ${name} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${EXE} ${name} --help failed (${rc})")
  endif()
  string(APPEND text "\n\n==== brushtrace ${name} ====\n\n${help}")
endforeach()
# CLI11 prints argv[0]: the build tree's path, which means nothing where the text is installed.
string(REPLACE "${EXE}" "brushtrace" text "${text}")
file(WRITE "${OUT}.tmp" "${text}")
file(RENAME "${OUT}.tmp" "${OUT}")
