# Installs the project into a prefix under the build directory, then builds and runs consumers
# out of tree: find_package(aerial CONFIG) with every component (C, C++, OpenSceneGraph, mesh
# grading through the validation component against the installed aerial-tess); C-only
# consumers of COMPONENTS core and core;gl with the C++ dependencies' find_package disabled; the
# installed tools; the C program with pkg-config's aerial-core and aerial. Run with cmake -P and:
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

# The flags `pkg-config --cflags --libs PACKAGE` gives, as a list in `var`.
function(pkg_config_flags var package)
    execute_process(COMMAND pkg-config --cflags --libs ${package} RESULT_VARIABLE rc
                    OUTPUT_VARIABLE flags ERROR_VARIABLE err OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "pkg-config --cflags --libs ${package} failed: ${err}")
    endif()
    separate_arguments(flags UNIX_COMMAND "${flags}")
    set(${var} ${flags} PARENT_SCOPE)
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
if(EXISTS ${WORK_DIR}/build/consumer_osg)
    run(${WORK_DIR}/build/consumer_osg)
elseif(EXISTS ${prefix}/lib/cmake/aerial/aerial-osg-targets.cmake)
    message(FATAL_ERROR "the package has the osg component, but consumer_osg was not built")
endif()

# Grading meshes from C++ with the validation component.
include(${CMAKE_CURRENT_LIST_DIR}/check_grading.cmake)

# A C-only consumer of the core, then of core and gl, with every C++ dependency's find_package
# disabled: the components it asks for need none of them.
foreach(components core "core;gl")
    string(REPLACE ";" "-" name "${components}")
    run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/c_only -B ${WORK_DIR}/c_only-${name} -G ${GENERATOR}
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
        -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "-DCOMPONENTS=${components}"
        -DCMAKE_DISABLE_FIND_PACKAGE_hwy=ON -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON
        -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_glm=ON)
    run(${CMAKE_COMMAND} --build ${WORK_DIR}/c_only-${name})
    run(${WORK_DIR}/c_only-${name}/consumer_c_only)
endforeach()
# A component the package does not have is an error naming it.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/c_only -B ${WORK_DIR}/c_only-bad
                        -G ${GENERATOR} -DCMAKE_PREFIX_PATH=${prefix} "-DCOMPONENTS=core;vulkan"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT "${out}${err}" MATCHES "unknown component 'vulkan'")
    message(FATAL_ERROR "COMPONENTS vulkan: expected an error naming it, got (${rc}):\n${out}${err}")
endif()

# The tools come with the package.
foreach(tool aerial-eval aerial-compare aerial-render aerial-regress aerial-tess)
    run(${prefix}/bin/${tool} --help)
endforeach()
if(NOT EXISTS ${prefix}/share/aerial/golden/suite.txt)
    message(FATAL_ERROR "the regression suite is not installed: ${prefix}/share/aerial/golden/suite.txt")
endif()

# pkg-config, per component: the C program with aerial-core's flags only.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
pkg_config_flags(flags aerial-core)
run(${C_COMPILER} -std=c89 -pedantic -Werror ${SOURCE_DIR}/consumer.c -o ${WORK_DIR}/consumer_c_core_pc
    ${flags})
run(${WORK_DIR}/consumer_c_core_pc)
foreach(component gl headless mesh scene validation)
    run(pkg-config --exists --print-errors aerial-${component})
endforeach()

# pkg-config: the C program with nothing but the flags the package's aerial.pc gives.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
pkg_config_flags(flags aerial)
run(${C_COMPILER} -std=c89 -pedantic -Werror ${SOURCE_DIR}/consumer.c -o ${WORK_DIR}/consumer_c_pkgconfig
    ${flags})
run(${WORK_DIR}/consumer_c_pkgconfig)
