# The drivers' answers to bad command lines, before any scene loads: exit 2 and what was wrong.
# Run by CTest: cmake -DCORE=<core_bench> -DDACRT=<dacrt_bench> -DSHAFTS=<shafts_bench>
#   -DMANYLIGHT=<manylight_bench> -P bench_option_errors.cmake
function(expect pattern driver)
  execute_process(COMMAND ${driver} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 2 OR NOT err MATCHES "${pattern}")
    message(FATAL_ERROR "expected exit 2 and '${pattern}': ${driver} ${ARGN}\nexit ${rc}\n${out}${err}")
  endif()
endfunction()

# An empty list printed headings without rows and exited 0.
expect("error: --scenes: empty" ${SHAFTS} --scenes ,)
expect("error: --workloads: empty" ${SHAFTS} --workloads ,)
expect("error: --scenes: unknown ','" ${MANYLIGHT} --scenes ,)
# A key given twice is an error, not "the last one wins".
expect("option 'dir_res' given twice \\('3' and '4'\\)" ${SHAFTS} --accel-opt dir_res=3 --accel-opt dir_res=4)
expect("--column 'a:bvh:bins=8,bins=9': option 'bins' given twice \\('8' and '9'\\)" ${CORE} --column a:bvh:bins=8,bins=9)
# A misspelt accelerator option ends the run before a scene loads. An error in a --column or
# --variants names the argument it came from: there may be several.
expect("accelerator 'shafts' has no option\\(s\\): nosuch" ${SHAFTS} --accel-opt nosuch=1)
expect("--column 'a:nosuch': unknown accelerator 'nosuch'" ${CORE} --column a:nosuch)
expect("error: --column 'bvh-x:bvh:colapse=sah': accelerator 'bvh' has no option\\(s\\): colapse"
       ${CORE} --column b:bvh:bins=8 --column bvh-x:bvh:colapse=sah)
expect("--column 'b:bvh:bins=1': option 'bins': 1 is not in \\[2, 256\\]" ${CORE} --column b:bvh:bins=1)
expect("error: --variants 'cs:dacrt-rs:skp=on': accelerator 'dacrt-rs' has no option\\(s\\): skp"
       ${DACRT} --variants a:skip=on --variants cs:dacrt-rs:skp=on)
# --variants takes --column's form; the older label=key:value;... is refused, naming the form.
expect("--variants 'a=cost:sampled': expected label\\[:accel\\]\\[:key=value,...\\]" ${DACRT} --variants a=cost:sampled)
expect("--variants 'a:bvh:bins=8': unknown 'bvh' \\(known: dacrt, dacrt-rs\\)" ${DACRT} --variants a:bvh:bins=8)
# budget_mib would override every budget_rel row of the sweep.
expect("--sweep varies budget_rel, which --accel-opt budget_mib overrides" ${SHAFTS} --sweep --accel-opt budget_mib=8)
