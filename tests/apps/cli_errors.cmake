# Bad command lines and bad files: each must exit with the expected code and say what was wrong.
# Run by CTest: cmake -DRAYSCOUT=<binary> -DWORK=<dir> -P cli_errors.cmake
file(MAKE_DIRECTORY ${WORK})
function(expect code pattern)
  execute_process(COMMAND ${RAYSCOUT} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL ${code})
    message(FATAL_ERROR "exit ${rc}, expected ${code}: rayscout ${ARGN}\n${out}${err}")
  endif()
  if(NOT "${out}${err}" MATCHES "${pattern}")
    message(FATAL_ERROR "output does not match '${pattern}': rayscout ${ARGN}\n${out}${err}")
  endif()
endfunction()

expect(0 "Usage" --help)
expect(0 "--accel" trace --help)
expect(2 "A subcommand is required|subcommand")
expect(2 "--scene is required" rays --workload primary --out ${WORK}/x.rays)
expect(2 "--no-such-option" render --no-such-option)
expect(2 "nope" render --accel nope --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "bogus" render --accel bvh --accel-opt bogus=1 --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "missing\\.obj" render --scene ${WORK}/missing.obj --out ${WORK}/x.png)

# A ray file cut short and one with a wrong magic word.
expect(0 "wrote" rays --scene cornell --workload primary --width 8 --height 8 --out ${WORK}/ok.rays)
execute_process(COMMAND head -c 100 ${WORK}/ok.rays OUTPUT_FILE ${WORK}/cut.rays)
expect(2 "cut\\.rays" trace --scene cornell --rays ${WORK}/cut.rays --accel bvh)
file(WRITE ${WORK}/bad.rays "RAYX")
expect(2 "bad\\.rays" trace --scene cornell --rays ${WORK}/bad.rays --accel bvh)

# A command's own verdict keeps its code: compare-hits of two different hit sets exits 1.
expect(0 "wrote" rays --scene cornell --workload diffuse --width 8 --height 8 --out ${WORK}/d.rays)
expect(0 "mrays_per_s" trace --scene cornell --rays ${WORK}/ok.rays --accel bvh --out ${WORK}/p.hits)
expect(0 "mrays_per_s" trace --scene cornell --rays ${WORK}/d.rays --accel bvh --out ${WORK}/d.hits)
expect(1 "result" compare-hits ${WORK}/p.hits ${WORK}/d.hits)
