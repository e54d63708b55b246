# Included by run_consumer.cmake (its run() and variables): grading from the installed package.
# The installed aerial-tess grades its built-in meshes on a dome and a terrain scene and exports
# them as OBJ; consumer_grade, built against the installed validation component, reads two of
# those files (one dome, one terrain) and grades them through the C++ API. Every figure must
# equal aerial-tess's row of that mesh, bit for bit as printed.
set(grade_dir ${WORK_DIR}/grade)
set(scenes ${SOURCE_DIR}/data/grade_scenes.json)
run(${prefix}/bin/aerial-tess --quick --no-chart --face-pixels 32 --scenes ${scenes}
    --export-meshes ${grade_dir}/meshes --out ${grade_dir}/tess)
set(dome_mesh ${grade_dir}/meshes/dome-sun10-g0.90/adaptive-2.obj)
set(terrain_mesh ${grade_dir}/meshes/terrain-eye300-sun10/adaptive-2.obj)
execute_process(COMMAND ${WORK_DIR}/build/consumer_grade ${scenes} 32 ${dome_mesh} ${terrain_mesh}
                RESULT_VARIABLE rc OUTPUT_VARIABLE graded ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer_grade failed (${rc}): ${err}")
endif()
message(STATUS "consumer_grade:\n${graded}")
file(STRINGS ${grade_dir}/tess/tess.csv rows)
string(REPLACE "\n" ";" graded "${graded}")
set(compared 0)
foreach(line ${graded})
    if(line STREQUAL "")
        continue()
    endif()
    # SCENE,FILE,FIGURES... against tess.csv's SCENE,adaptive,2,FIGURES,face_pixels,...
    string(REGEX MATCH "^([^,]+),[^,]+,(.*)$" _ "${line}")
    set(scene ${CMAKE_MATCH_1})
    set(figures ${CMAKE_MATCH_2})
    set(found "")
    foreach(row ${rows})
        if(row MATCHES "^${scene},adaptive,2,")
            set(found "${row}")
        endif()
    endforeach()
    if(NOT found MATCHES "^${scene},adaptive,2,${figures},")
        message(FATAL_ERROR "graded from the installed package: ${line}\naerial-tess's row: ${found}")
    endif()
    math(EXPR compared "${compared} + 1")
endforeach()
if(NOT compared EQUAL 2)
    message(FATAL_ERROR "expected a dome and a terrain mesh graded, got ${compared}: ${graded}")
endif()
