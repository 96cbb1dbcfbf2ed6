# CLI round trip: rayscout rays -> trace (bvh, embree) -> compare-hits, on the built-in scene.
# Run by CTest: cmake -DRAYSCOUT=<binary> -DWORK=<dir> -P cli_round_trip.cmake
file(MAKE_DIRECTORY ${WORK})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()
foreach(workload primary diffuse)
  run(${RAYSCOUT} rays --scene cornell --workload ${workload} --width 64 --height 64 --out ${WORK}/${workload}.rays)
  foreach(accel bvh embree)
    run(${RAYSCOUT} trace --scene cornell --rays ${WORK}/${workload}.rays --accel ${accel} --repeat 1
        --out ${WORK}/${workload}_${accel}.hits)
    if(NOT last_output MATCHES "\"accel\":\"${accel}\".*\"mrays_per_s\"")
      message(FATAL_ERROR "trace printed no JSON line for ${accel}")
    endif()
  endforeach()
  run(${RAYSCOUT} compare-hits ${WORK}/${workload}_bvh.hits ${WORK}/${workload}_embree.hits --tolerance 1e-4)
  run(${RAYSCOUT} compare-hits ${WORK}/${workload}_bvh.hits ${WORK}/${workload}_embree.hits --tolerance 1e-4
      --rays ${WORK}/${workload}.rays)
  if(NOT last_output MATCHES "world space")
    message(FATAL_ERROR "compare-hits --rays did not judge distances in world space")
  endif()
endforeach()
run(${RAYSCOUT} rays --scene cornell --workload shadow --width 64 --height 64 --out ${WORK}/shadow.rays)
foreach(accel bvh embree)
  run(${RAYSCOUT} trace --scene cornell --rays ${WORK}/shadow.rays --accel ${accel} --occluded --repeat 1
      --out ${WORK}/shadow_${accel}.occl)
endforeach()
run(${RAYSCOUT} compare-hits ${WORK}/shadow_bvh.occl ${WORK}/shadow_embree.occl)
# With both sides' closest hits of the same rays, grazing blockers are reported (and excused).
foreach(accel bvh embree)
  run(${RAYSCOUT} trace --scene cornell --rays ${WORK}/shadow.rays --accel ${accel} --repeat 1
      --out ${WORK}/shadow_${accel}.hits)
endforeach()
run(${RAYSCOUT} compare-hits ${WORK}/shadow_bvh.occl ${WORK}/shadow_embree.occl --rays ${WORK}/shadow.rays
    --hits-a ${WORK}/shadow_bvh.hits --hits-b ${WORK}/shadow_embree.hits)
if(NOT last_output MATCHES "grazing contacts: +0")
  message(FATAL_ERROR "compare-hits --hits-a/--hits-b printed no grazing count")
endif()
execute_process(COMMAND ${RAYSCOUT} compare-hits ${WORK}/shadow_bvh.occl ${WORK}/shadow_embree.occl
                        --hits-a ${WORK}/shadow_bvh.hits
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "go together")
  message(FATAL_ERROR "compare-hits with --hits-a alone returned ${rc}: ${err}")
endif()
# A file compared with a different one must fail with exit 1.
execute_process(COMMAND ${RAYSCOUT} compare-hits ${WORK}/primary_bvh.hits ${WORK}/diffuse_embree.hits
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "compare-hits of different ray sets returned ${rc}, expected 1")
endif()
# --rays of another size than the hits is an input error (exit 2), naming the file.
run(${RAYSCOUT} rays --scene cornell --width 8 --height 8 --out ${WORK}/small.rays)
execute_process(COMMAND ${RAYSCOUT} compare-hits ${WORK}/primary_bvh.hits ${WORK}/primary_embree.hits
                        --rays ${WORK}/small.rays
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "small.rays: 64 rays")
  message(FATAL_ERROR "compare-hits with a RAYS file of another size returned ${rc}: ${err}")
endif()
# render --count on an accelerator that keeps no work counters (Embree) says so, and neither
# prints a line of zero counts nor writes zeros as its counters into --stats (trace's null).
execute_process(COMMAND ${RAYSCOUT} render --accel embree --count --width 8 --height 8 --spp 1 --out ${WORK}/count.png
                        --stats ${WORK}/count.json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT err MATCHES "--count: embree has no work counters" OR "${out}${err}" MATCHES "work:")
  message(FATAL_ERROR "render --accel embree --count (exit ${rc}):\n${out}${err}")
endif()
file(READ ${WORK}/count.json stats)
string(JSON counters_type ERROR_VARIABLE json_error TYPE "${stats}" counters)
string(JSON counters_note ERROR_VARIABLE note_error GET "${stats}" counters_note)
if(NOT counters_type STREQUAL "NULL" OR note_error OR stats MATCHES "traversal_steps")
  message(FATAL_ERROR "render --accel embree --count --stats: counters are not null with a note:\n${stats}")
endif()
