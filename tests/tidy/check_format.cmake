# ctest `clang_format`: every C++ file of the project is formatted as .clang-format says.
#   cmake -DCLANG_FORMAT=/usr/bin/clang-format -DSOURCE_DIR=<repo> -P check_format.cmake
# Prints the files that differ (and how to fix them) and fails; nothing is rewritten.
file(GLOB_RECURSE files RELATIVE ${SOURCE_DIR}
     ${SOURCE_DIR}/include/*.hpp ${SOURCE_DIR}/src/*.hpp ${SOURCE_DIR}/src/*.cpp ${SOURCE_DIR}/tests/*.hpp
     ${SOURCE_DIR}/tests/*.cpp ${SOURCE_DIR}/benchmarks/*.hpp ${SOURCE_DIR}/benchmarks/*.cpp
     ${SOURCE_DIR}/examples/*.cpp ${SOURCE_DIR}/tests/*.cu ${SOURCE_DIR}/examples/*.cu)
list(LENGTH files count)
set(bad "")
foreach(f IN LISTS files)
  execute_process(COMMAND ${CLANG_FORMAT} --dry-run --Werror ${f} WORKING_DIRECTORY ${SOURCE_DIR}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    list(APPEND bad ${f})
  endif()
endforeach()
if(bad)
  list(LENGTH bad n)
  string(REPLACE ";" "\n  " listing "${bad}")
  message(FATAL_ERROR "clang-format: ${n} of ${count} files are not formatted:\n  ${listing}\n"
                      "fix: cd ${SOURCE_DIR} && clang-format -i <files>")
endif()
message(STATUS "clang-format: all ${count} files formatted")
