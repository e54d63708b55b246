# Installs the project into a prefix under the build directory, then builds and runs the
# consumer out of tree: with find_package(aerial CONFIG) (C and C++), and the C program alone
# with `pkg-config --cflags --libs aerial`. Run with cmake -P and:
#   -DBUILD_DIR=  the project's build directory     -DSOURCE_DIR= tests/consumer
#   -DWORK_DIR=   scratch directory (wiped)         -DGENERATOR=  CMake generator
#   -DC_COMPILER= the C compiler for the pkg-config build
cmake_minimum_required(VERSION 3.20)

function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message(STATUS "$ ${ARGN}\n${out}${err}")
    if(NOT rc EQUAL 0)
        string(REPLACE ";" " " cmd "${ARGN}")
        message(FATAL_ERROR "failed (${rc}): ${cmd}")
    endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# CMake: find_package(aerial CONFIG REQUIRED) from the installed prefix only.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer_c)
run(${WORK_DIR}/build/consumer_cpp)

# pkg-config: the C program with nothing but the flags the package's aerial.pc gives.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
execute_process(COMMAND pkg-config --cflags --libs aerial RESULT_VARIABLE rc
                OUTPUT_VARIABLE flags ERROR_VARIABLE err OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "pkg-config --cflags --libs aerial failed: ${err}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${C_COMPILER} -std=c89 -pedantic -Werror ${SOURCE_DIR}/consumer.c -o ${WORK_DIR}/consumer_c_pkgconfig
    ${flags})
run(${WORK_DIR}/consumer_c_pkgconfig)
