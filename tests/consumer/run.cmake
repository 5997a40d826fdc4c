# One step of the consumer tests (CMakeLists.txt here), run as `cmake -P run.cmake`:
#   -DMODE=install  -DBUILD=<pce's build> -DPREFIX=<dir> [-DCOMPONENT=<c>] [-DCONFIG=<cfg>]
#       a fresh `cmake --install` of pce into PREFIX (removed first: nothing stale counts)
#   -DMODE=consume  -DBINARY=<dir> -DGENERATOR=... -DCXX=... -DCONFIG=<cfg> [-DSIM=ON]
#       [-DPREFIX=<dir> | -DPCE_SOURCE=<pce's source tree> | -DPCE_GIT=<pce's git URL>] [-DEXPECT_VERSION=<v>]
#       [-DEIGEN3_DIR=<dir>] [-DWERROR=ON] [-DPIC=ON|OFF] [-DEXPECT_FAIL=<regex>] [-DCONFIGURE_ONLY=ON]
#       [-DCUDA=<nvcc>]
#       configures project/ in a fresh BINARY, builds it and runs its programs; with
#       EXPECT_FAIL, the configuration must fail with a message matching the regex; with
#       CONFIGURE_ONLY, it is only configured (its own checks run at configure time); with
#       CUDA, the CUDA file is built and run too (it exits 0 without a device).
cmake_minimum_required(VERSION 3.16)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${cmd}")
  endif()
endfunction()

if(MODE STREQUAL "install")
  file(REMOVE_RECURSE ${PREFIX})
  set(component)
  if(COMPONENT)
    set(component --component ${COMPONENT})
  endif()
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${PREFIX} --config ${CONFIG} ${component})
  return()
endif()

file(REMOVE_RECURSE ${BINARY})
set(args -S ${CMAKE_CURRENT_LIST_DIR}/project -B ${BINARY} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX}
         -DCMAKE_BUILD_TYPE=${CONFIG} -DPCE_CONSUMER_SIM=${SIM} -DPCE_CONSUMER_EXPECT_VERSION=${EXPECT_VERSION}
         # only PREFIX may provide pce: no package registries, no system-wide pce
         -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
if(PREFIX)
  list(APPEND args -DCMAKE_PREFIX_PATH=${PREFIX} -DPCE_CONSUMER_EXPECT_PREFIX=${PREFIX})
endif()
if(PCE_SOURCE)
  list(APPEND args -DPCE_CONSUMER_SOURCE=${PCE_SOURCE} -DPCE_WERROR=${WERROR})
endif()
if(PCE_GIT)
  list(APPEND args -DPCE_CONSUMER_GIT=${PCE_GIT} -DPCE_WERROR=${WERROR})
endif()
if(EIGEN3_DIR)
  list(APPEND args -DEigen3_DIR=${EIGEN3_DIR})
endif()
if(DEFINED PIC AND NOT PIC STREQUAL "")
  list(APPEND args -DCMAKE_POSITION_INDEPENDENT_CODE=${PIC})
endif()

if(CUDA)
  list(APPEND args -DPCE_CONSUMER_CUDA=ON -DCMAKE_CUDA_COMPILER=${CUDA})
endif()

if(DEFINED EXPECT_FAIL)
  execute_process(COMMAND ${CMAKE_COMMAND} ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(rc EQUAL 0)
    message(FATAL_ERROR "the configuration succeeded; expected it to fail with: ${EXPECT_FAIL}")
  endif()
  string(REGEX REPLACE "[ \n]+" " " text "${err}")  # CMake wraps long messages
  if(NOT text MATCHES "${EXPECT_FAIL}")
    message(FATAL_ERROR "the configuration failed without saying: ${EXPECT_FAIL}")
  endif()
  return()
endif()

run(${CMAKE_COMMAND} ${args})
if(CONFIGURE_ONLY)
  return()
endif()
run(${CMAKE_COMMAND} --build ${BINARY} --config ${CONFIG})
set(programs consumer)
if(PREFIX OR SIM)  # project/CMakeLists.txt: where consumer_precompiled is built
  list(APPEND programs consumer_precompiled)
endif()
if(SIM)
  list(APPEND programs consumer_sim)
endif()
if(CUDA)
  list(APPEND programs consumer_cuda)
endif()
foreach(program IN LISTS programs)
  find_program(path_${program} ${program} PATHS ${BINARY} ${BINARY}/${CONFIG} NO_DEFAULT_PATH REQUIRED)
  run(${path_${program}})
endforeach()
