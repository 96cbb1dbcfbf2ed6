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
  set(last_output "${out}${err}" PARENT_SCOPE)
endfunction()
# As expect, and the output must not match `absent` either.
function(expect_without code pattern absent)
  expect(${code} "${pattern}" ${ARGN})
  if("${last_output}" MATCHES "${absent}")
    message(FATAL_ERROR "output matches '${absent}': rayscout ${ARGN}\n${last_output}")
  endif()
endfunction()

expect(0 "Usage" --help)
# Options several commands share have one help text, which lists the accelerators.
foreach(command render rays trace)
  expect(0 "--scene TEXT[ A-Z]*a \\.json scene file .* or cornell, the built-in Cornell box.*--accel TEXT=bvh +accelerator [a-z ]+: brute, dacrt, dacrt-rs, bvh2, bvh, shafts"
         ${command} --help)
endforeach()
# info on the built-in scene: its counts by hand (26 white, 2 red, 2 green, 2 light triangles;
# the light a 0.5 x 0.5 quad).
expect(0 "triangles: +32\nbounds: +min \\(-1, 0, -1\\) max \\(1, 2, 1\\)\n.*materials: +4\n +white +diffuse +26 tris.*\n +red +diffuse +2 tris.*\n +green +diffuse +2 tris.*\n +light +diffuse +2 tris .*emission \\(17, 12, 4\\)\nlights: +1 point, 2 emissive triangles \\(area 0\\.25\\)\n +point at \\(0, 1\\.9, 0\\)"
       info --scene cornell)
# info escapes the control bytes of material names, as errors and warnings do: a material named
# "<ESC>[2J" cleared the terminal.
string(ASCII 27 esc)
file(WRITE ${WORK}/esc.mtl "newmtl paint${esc}[2J\nKd 0.5 0.5 0.5\n")
file(WRITE ${WORK}/esc.obj "mtllib esc.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl paint${esc}[2J\nf 1 2 3\n")
file(COPY_FILE ${WORK}/esc.obj ${WORK}/esc${esc}c.obj)
expect_without(0 "\n  paint\\\\x1b\\[2J +diffuse +1 tris" "${esc}" info --scene ${WORK}/esc.obj)
# So does every error that quotes a path or an argument the CLI checked itself (an output
# folder, an option CLI11 did not expect, a misspelt command): they printed the bytes raw.
expect_without(2 "--out .*no\\\\x1b\\[2J/x\\.png: folder .*no\\\\x1b\\[2J does not exist" "${esc}"
               render --width 8 --height 8 --out ${WORK}/no${esc}[2J/x.png)
expect_without(2 "not expected: --x\\\\x1b\\[2J\n" "${esc}" render --x${esc}[2J)
expect_without(2 "unknown command 'r\\\\x1b\\[2J'" "${esc}" r${esc}[2J)
# The summaries and warnings that name a file escape it too (ESC c resets a terminal; a '['
# would group a CMake list's arguments).
expect_without(0 "wrote .*e\\\\x1bc\\.png \\(8x8" "${esc}" render --width 8 --height 8 --spp 1 --out ${WORK}/e${esc}c.png)
expect_without(0 "wrote .*e\\\\x1bc\\.pfm" "${esc}" render --width 8 --height 8 --spp 1 --out ${WORK}/e${esc}c.pfm)
expect_without(0 "wrote .*d\\\\x1bc\\.png.*warning: .*e\\\\x1bc\\.png is a PNG.*e\\\\x1bc\\.pfm is not" "${esc}"
               diff ${WORK}/e${esc}c.png ${WORK}/e${esc}c.pfm --out ${WORK}/d${esc}c.png)
# The PNG warning whichever side the PNG is on (a check of A alone passed the case above).
expect(0 "warning: .*e\\\\x1bc\\.png is a PNG \\(8-bit sRGB.* and .*e\\\\x1bc\\.pfm is not"
       diff ${WORK}/e${esc}c.pfm ${WORK}/e${esc}c.png)
expect_without(0 "scene: .*esc\\\\x1bc\\.obj" "${esc}" info --scene ${WORK}/esc${esc}c.obj)
expect(0 "--accel" trace --help)
expect(0 "^rayscout [0-9]+\\.[0-9]+" --version)
expect(2 "unknown option '--width' \\(options follow the command" --width 8 render)
expect(0 "Integrators \\(--integrator\\):.*direct +point lights.*manylight +VPLs" render --help)
expect(2 "A subcommand is required|subcommand")
expect(2 "unknown command 'rendr' \\(commands: accelerators, .*render, trace" rendr --out ${WORK}/x.png)
expect(2 "--scene is required" rays --workload primary --out ${WORK}/x.rays)
expect(2 "--no-such-option" render --no-such-option)
# CLI11's usage errors read as rayscout's own and name the command's --help.
expect(2 "^rayscout: error: The following argument was not expected: --no-such-option\nRun 'rayscout render --help'"
       render --no-such-option)
expect(2 "^rayscout: error: --scene is required\nRun 'rayscout trace --help'" trace --rays ${WORK}/x.rays)
# An empty file name is refused: --scene "" rendered the built-in Cornell box, --stats "" wrote
# nothing, and both exited 0. (The empty argument is written out here: a CMake list drops it.)
function(expect_empty_path option)
  execute_process(COMMAND ${RAYSCOUT} ${ARGN} ${option} "" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 2 OR NOT "${out}${err}" MATCHES "^rayscout: error: ${option}: an empty path names no file\n")
    message(FATAL_ERROR "exit ${rc}, expected 2 and '${option}: an empty path names no file': "
                        "rayscout ${ARGN} ${option} \"\"\n${out}${err}")
  endif()
endfunction()
expect_empty_path(--scene render)
expect_empty_path(--stats render)
expect_empty_path(--out render)
expect_empty_path(--rmse-log render --integrator manylight)
expect_empty_path(--reference render --integrator manylight)
expect_empty_path(--skip-image render --integrator manylight)
expect_empty_path(--rays trace --scene cornell)
expect_empty_path(--out trace --scene cornell --rays ${WORK}/x.rays)
expect_empty_path(--out rays --scene cornell)
expect_empty_path(--out diff a.png b.png)
# "-" is stdout only for render's --stats: as another output it wrote a file called '-' (rays
# then said "wrote 64 primary rays ... to -").
foreach(cmdline "rays --scene cornell --width 8 --height 8" "trace --scene cornell --rays x.rays" "render"
                "render --integrator manylight --skip-image" "render --integrator manylight --rmse-log" "diff a.png b.png")
  separate_arguments(args UNIX_COMMAND "${cmdline}")
  set(option --out)
  if(cmdline MATCHES "(--skip-image|--rmse-log)$")
    set(option ${CMAKE_MATCH_1})
    list(REMOVE_AT args -1)
  endif()
  expect(2 "^rayscout: error: ${option}: '-' is not standard output here: name a file \\(\\./- for one called '-'\\)\n"
         ${args} ${option} -)
endforeach()
# diff's positionals are named A and B, as its description and compare-hits name them.
expect(2 "^rayscout: error: B is required\nRun 'rayscout diff --help'" diff a.png)
expect_empty_path(--hits-a compare-hits a.occl b.occl)
# A misspelt integrator or workload is a usage error naming the option, found as the command line
# is parsed, not after a warning that --max-depth is "ignored by --integrator pth".
expect_without(2 "--integrator: pth not in {direct,area,ao,path,manylight}" "warning"
               render --integrator pth --max-depth 2 --width 8 --height 8 --out ${WORK}/x.png)
expect_without(2 "--workload: aoo not in {primary,shadow,ao,diffuse}" "warning"
               rays --scene cornell --workload aoo --ao-radius 1 --out ${WORK}/x.rays)
expect(2 "nope" render --accel nope --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "bogus" render --accel bvh --accel-opt bogus=1 --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "missing\\.obj" render --scene ${WORK}/missing.obj --out ${WORK}/x.png)
# Accelerator names and options are checked before a scene or ray file is read.
expect(2 "unknown accelerator 'nope'" render --scene ${WORK}/missing.obj --accel nope --out ${WORK}/x.png)
expect(2 "has no option\\(s\\): budgt" trace --scene ${WORK}/missing.obj --rays ${WORK}/missing.rays --accel shafts --accel-opt budgt=3)
expect(2 "unknown accelerator 'nope'" rays --scene ${WORK}/missing.obj --workload primary --accel nope --out ${WORK}/x.rays)

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
expect_without(1 "result" "hint" compare-hits ${WORK}/p.hits ${WORK}/d.hits)
# Hits that differ in t alone (the same quad moved 0.01 along its normal) name --rays, which
# judges such differences in world space (embree against bvh on Sponza failed without it).
foreach(z 0 0.01)
  file(WRITE ${WORK}/quad${z}.json "{\"meshes\": [{\"shape\": \"quad\", \"corner\": [-10, -10, ${z}], \"edge1\": [20, 0, 0], \"edge2\": [0, 20, 0]}], \"camera\": {\"eye\": [0, 0, 2], \"look_at\": [0, 0, 0]}, \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 2]}]}")
endforeach()
expect(0 "wrote" rays --scene ${WORK}/quad0.json --width 8 --height 8 --out ${WORK}/quad.rays)
foreach(z 0 0.01)
  expect(0 "mrays_per_s" trace --scene ${WORK}/quad${z}.json --rays ${WORK}/quad.rays --out ${WORK}/quad${z}.hits)
endforeach()
expect(1 "t beyond tolerance: +64\n.*result: +DIFFERENT.*\nhint: .*--rays FILE" compare-hits ${WORK}/quad0.hits ${WORK}/quad0.01.hits)
expect_without(1 "result: +DIFFERENT" "hint" compare-hits ${WORK}/quad0.hits ${WORK}/quad0.01.hits --rays ${WORK}/quad.rays)
# trace's JSON line: the count of the hits it wrote (compare-hits counts them in the file) and
# exact work counters, brute force testing each of 64 rays against the 32 triangles of the
# Cornell box. The diffuse rays leave by the open side too: some hit, some miss.
foreach(query intersect occluded)
  set(flag "")
  set(key hits)
  set(ext hits)
  if(query STREQUAL "occluded")
    set(flag --occluded)
    set(key occluded)
    set(ext occl)
  endif()
  execute_process(COMMAND ${RAYSCOUT} trace --scene cornell --rays ${WORK}/d.rays --accel brute --count --repeat 1
                          ${flag} --out ${WORK}/d_brute.${ext}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(JSON positives ERROR_VARIABLE json_error GET "${out}" ${key})
  string(JSON counted_rays ERROR_VARIABLE json_error2 GET "${out}" counters rays)
  string(JSON tri_tests ERROR_VARIABLE json_error3 GET "${out}" counters ray_tri_tests)
  string(JSON box_tests ERROR_VARIABLE json_error4 GET "${out}" counters ray_box_tests)
  execute_process(COMMAND ${RAYSCOUT} compare-hits ${WORK}/d_brute.${ext} ${WORK}/d_brute.${ext} OUTPUT_VARIABLE cmp)
  if(NOT rc EQUAL 0 OR json_error OR json_error2 OR json_error3 OR json_error4 OR positives EQUAL 0 OR positives EQUAL 64
     OR NOT cmp MATCHES "${key}: +${positives} in A" OR NOT counted_rays EQUAL 64 OR NOT box_tests EQUAL 0
     OR (query STREQUAL "intersect" AND NOT tri_tests EQUAL 2048)
     OR (query STREQUAL "occluded" AND (tri_tests GREATER_EQUAL 2048 OR tri_tests LESS 64)))
    message(FATAL_ERROR "trace --count (${query}): wrong JSON line (exit ${rc}):\n${out}${err}\ncompare-hits:\n${cmp}")
  endif()
endforeach()
# A candidate that claims t = 0 on another triangle for every hit would excuse itself as grazing
# contacts: beyond --max-grazing (1 % of the rays) the files differ.
execute_process(COMMAND /usr/bin/python3 -c "import struct,sys; b=bytearray(open(sys.argv[1],'rb').read())
for o in range(16, len(b), 16):
    if struct.unpack_from('<I', b, o + 4)[0] != 0xFFFFFFFF: struct.pack_into('<fI', b, o, 0.0, struct.unpack_from('<I', b, o + 4)[0] ^ 1)
open(sys.argv[2], 'wb').write(b)" ${WORK}/p.hits ${WORK}/t0.hits RESULT_VARIABLE rc)
expect(1 "too many grazing: +[0-9]+ of 64 rays, above --max-grazing 0.01" compare-hits ${WORK}/p.hits ${WORK}/t0.hits --rays ${WORK}/ok.rays)
expect(0 "result: +OK" compare-hits ${WORK}/p.hits ${WORK}/t0.hits --max-grazing 1)
# With the scene, contacts are judged from the triangles: t = 0 on another triangle, far from
# its edges and its plane, excuses nothing however many --max-grazing allows.
expect(1 "different triangle: +[1-9][0-9]* .*\ngrazing contacts: +0 \\(an edge, an end of the segment or two distances within 4 float ulps of the coordinates; not counted\\).*result: +DIFFERENT"
       compare-hits ${WORK}/p.hits ${WORK}/t0.hits --rays ${WORK}/ok.rays --scene cornell --max-grazing 1)
expect_without(0 "result: +OK" "warning" compare-hits ${WORK}/p.hits ${WORK}/p.hits --rays ${WORK}/ok.rays --scene cornell)
expect(2 "--scene judges contacts from the rays' geometry: give the RAYS file too \\(--rays FILE\\)"
       compare-hits ${WORK}/p.hits ${WORK}/p.hits --scene cornell)
expect(2 "p\\.hits: ray [0-9]+ hits triangle [0-9]+, but --scene .*quad0\\.json has 2 triangles \\(traced against another scene\\?\\)"
       compare-hits ${WORK}/p.hits ${WORK}/p.hits --rays ${WORK}/ok.rays --scene ${WORK}/quad0.json)
expect(0 "warning: --edge-eps ignored with --scene" compare-hits ${WORK}/p.hits ${WORK}/p.hits --rays ${WORK}/ok.rays
       --scene cornell --edge-eps 0.01)
expect(0 "warning: --ulps ignored without --scene" compare-hits ${WORK}/p.hits ${WORK}/p.hits --ulps 8)
# --strict excuses no grazing contact, whatever --max-grazing allows; the default tolerance is 1e-4.
expect(1 "result: +DIFFERENT" compare-hits ${WORK}/p.hits ${WORK}/t0.hits --max-grazing 1 --strict)
expect(0 "result: +OK \\(tolerance 0\\.0001\\)" compare-hits ${WORK}/p.hits ${WORK}/p.hits)
# Every file of a comparison holds as many results as the first (or the RAYS file), whichever
# position the odd one is in; --hits-a/--hits-b belong to OCCL files.
expect(0 "wrote" rays --scene cornell --workload primary --width 4 --height 4 --out ${WORK}/small.rays)
expect(0 "mrays_per_s" trace --scene cornell --rays ${WORK}/small.rays --accel bvh --out ${WORK}/small.hits)
expect(2 "p\\.hits: 64 hits, but .*small\\.hits holds 16 hits" compare-hits ${WORK}/p.hits ${WORK}/small.hits)
expect(2 "ok\\.rays: 64 rays, but .*small\\.hits holds 16 hits" compare-hits ${WORK}/p.hits ${WORK}/small.hits --rays ${WORK}/ok.rays)
expect(2 "--hits-a and --hits-b are for OCCL files" compare-hits ${WORK}/p.hits ${WORK}/d.hits --hits-a ${WORK}/p.hits)
expect(0 "mrays_per_s" trace --scene cornell --rays ${WORK}/ok.rays --accel bvh --occluded --out ${WORK}/p.occl)
expect(2 "small\\.hits holds 16 hits" compare-hits ${WORK}/p.occl ${WORK}/p.occl --hits-a ${WORK}/p.hits --hits-b ${WORK}/small.hits)
expect(2 "a RAYS file, expected a HITS or OCCL file" compare-hits ${WORK}/ok.rays ${WORK}/p.hits)
# Two OCCL files are compared flag by flag; the distance and grazing options only judge the
# closest hits of --hits-a/--hits-b: without them they are said to be ignored.
expect(0 "warning: --tolerance, --strict are ignored comparing OCCL files without --hits-a and --hits-b"
       compare-hits ${WORK}/p.occl ${WORK}/p.occl --tolerance 0 --strict)
expect_without(0 "result: +OK" "warning" compare-hits ${WORK}/p.occl ${WORK}/p.occl --tolerance 0 --strict
               --hits-a ${WORK}/p.hits --hits-b ${WORK}/p.hits)

# Option values out of range: exit 2 naming the option and the value, before any work (never a
# hang, a wrapped unsigned value or a silent fallback to the default).
set(R render --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "--threads: '-3' is not an integer >= 0" ${R} --threads -3)
expect(2 "--ao-radius: 'nan' is not a number >= 0" ${R} --integrator ao --ao-radius nan)
expect(2 "--ray-epsilon: '-1' is not a number >= 0" ${R} --ray-epsilon -1)
expect(2 "--max-batch: '-5' is not an integer >= 0" ${R} --max-batch -5)
expect(2 "--seed: '-1' is not an integer" ${R} --seed -1)
expect(2 "--seed: '18446744073709551616' is not an integer" ${R} --seed 18446744073709551616)
expect(2 "--width: '100000' is not an integer in \\[1, 32768\\]" ${R} --width 100000)
# A number that is not an integer said "'1e3' is not a number", which it is.
expect(2 "--spp: '1e3' is not an integer in \\[1, 65536\\]" ${R} --spp 1e3)
expect(2 "--width: '16.5' is not an integer in \\[1, 32768\\]" ${R} --width 16.5)
expect(2 "--vpls: '-1' is not an integer" ${R} --integrator manylight --vpls -1)
expect(2 "--vpls: '0' is not an integer" ${R} --integrator manylight --vpls 0)
expect(2 "--passes: '-1' is not an integer in \\[1, 2147483647\\]" ${R} --integrator manylight --passes -1)
expect(2 "--passes: '4294967297' is not an integer in \\[1, 2147483647\\]" ${R} --integrator manylight --passes 4294967297
       --vpls 20 --time-budget 0.01)  # (the budget ends the render at once where the value is accepted)
expect(2 "--time-budget: 'inf' is not a number >= 0" ${R} --integrator manylight --time-budget inf)
expect(2 "--clamp-distance: '-1' is not a number >= 0" ${R} --integrator manylight --clamp-distance -1)
expect(2 "--visibility-samples: '0' is not an integer in \\[1, 65536\\]" ${R} --integrator manylight --visibility-samples 0)
expect(2 "--shading-clusters: '-4' is not an integer >= 1" ${R} --integrator manylight --shading-clusters -4)
expect(2 "--seed: '-1' is not an integer" rays --scene cornell --seed -1 --out ${WORK}/x.rays)
expect(2 "--ao-radius: '-1' is not a number >= 0" rays --scene cornell --workload ao --ao-radius -1 --out ${WORK}/x.rays)
# More rays than memory holds (here 137 GB): refused before the work, not killed by the kernel;
# a secondary workload holds the primary rays and hits too (112 bytes a ray).
expect(2 "--width 2147483647 x --height 1 x --spp 1 = 2147483647 rays \\(64 bytes a ray\\) need at least 137.4 GB, more than this machine's"
       rays --scene cornell --width 2147483647 --height 1 --out ${WORK}/x.rays)
expect(2 "= 1600000000 rays \\(112 bytes a ray\\) need at least 179.2 GB" rays --scene cornell --workload ao --width 40000 --height 40000 --out ${WORK}/x.rays)
# A render bigger than memory (here ~200,000 GB in one pass) is refused before the scene loads.
expect(2 "--width 32768 x --height 32768 \\(1073741824 pixels at 24 bytes for film and image, 1000000000000 camera rays a pass \\(--max-batch\\) at ~200 bytes\\) need at least"
       render --width 32768 --height 32768 --spp 1000 --max-batch 1000000000000 --out ${WORK}/x.exr)
# The occlusion rays of a hit share its batch (~110 GB here), and manylight's shading points are
# not split into passes (~140 GB): both counted.
expect(2 "16777216 camera rays a pass \\(--max-batch\\) at ~200 bytes with 64 occlusion rays each at ~100 bytes\\) need at least 11[0-9]\\.[0-9] GB"
       render --integrator ao --ao-samples 64 --width 4096 --height 4096 --spp 4 --out ${WORK}/x.png)
# Sizes whose sample count passes 2^32 are refused before the scene is read (it is missing here).
# The message gives the values and the way out.
expect(2 "render: width 1024 x height 1024 x spp 4096 = 4294967296 camera samples, more than 2\\^32 - 1 \\(sample ids are 32-bit\\): lower spp"
       render --scene ${WORK}/missing.obj --width 1024 --height 1024 --spp 4096 --max-batch 1000 --out ${WORK}/x.png)
# A ray offset of a sizeable part of the scene is warned about (rays would start past walls).
expect(0 "--ray-epsilon 0.5 is 14 % of the scene's diagonal"
       render --ray-epsilon 0.5 --width 8 --height 8 --out ${WORK}/x.png)
# From 1 % of the diagonal (3.46 here) on: 0.1 is 3 %, 0.03 is 0.9 %.
expect(0 "--ray-epsilon 0.1 is 3 % of the scene's diagonal"
       render --ray-epsilon 0.1 --width 8 --height 8 --out ${WORK}/x.png)
expect_without(0 "wrote" "ray-epsilon" render --ray-epsilon 0.03 --width 8 --height 8 --out ${WORK}/x.png)
# So do the shadow rays to point lights, known once the scene is loaded (64 lights here).
set(lights "")
foreach(i RANGE 1 64)
  string(APPEND lights "{\"type\": \"point\", \"position\": [0.5, 3, ${i}], \"intensity\": 1},")
endforeach()
string(REGEX REPLACE ",$" "" lights "${lights}")
file(WRITE ${WORK}/lights64.json "{\"meshes\": [{\"shape\": \"box\", \"min\": [0, 0, 0], \"max\": [1, 1, 1]}], \"lights\": [${lights}]}")
expect(2 "16777216 camera rays a pass \\(--max-batch\\) at ~200 bytes with 64 occlusion rays each at ~100 bytes \\(64 to point lights\\)\\) need at least 11[0-9]\\.[0-9] GB"
       render --scene ${WORK}/lights64.json --width 4096 --height 4096 --spp 4 --out ${WORK}/x.png)
# The shadow workload's ray per point light and hit too (~140 GB here; it was not counted).
expect(2 "--width 4096 x --height 4096 x --spp 2 = 33554432 rays \\(4144 bytes a ray, 64 shadow rays each\\) need at least 13[0-9]\\.[0-9] GB"
       rays --scene ${WORK}/lights64.json --workload shadow --width 4096 --height 4096 --spp 2 --out ${WORK}/x.rays)
expect(2 "1073741824 shading points at ~130 bytes\\) need at least 14[0-9]\\.[0-9] GB"
       render --integrator manylight --width 8192 --height 8192 --spp 16 --out ${WORK}/x.png)
# The shafts' camera pre-pass grows with prepass_width^2 (here ~40-64 GB): refused, not killed.
expect(2 "shafts pre-pass: prepass_width 16384 \\(201326592 pixels, up to [0-9]+ rays each at 32 bytes, twice while growing\\) needs at least"
       trace --scene cornell --rays ${WORK}/ok.rays --accel shafts --accel-opt select=camera --accel-opt prepass_width=16384)
expect(2 "--threads: '-3' is not an integer >= 0" trace --scene cornell --rays ${WORK}/ok.rays --threads -3)
expect(2 "--repeat: '0' is not an integer >= 1" trace --scene cornell --rays ${WORK}/ok.rays --repeat 0)
# Integers are decimal: CLI11 alone reads 010 as 8.
expect(0 "10x8" render --width 010 --height 8 --out ${WORK}/x.png)
expect(0 "in \\[1, 32768\\]" render --help)
# --help shows every option's default, or says that there is none.
expect(0 "--scale FLOAT:min 0=0 .*--max-rmse FLOAT:min 0 .*not given: always exit 0" diff --help)
expect(0 "--shading-clusters INT:min 1=512.*shading-point clusters, rounded up to a power of two, at most the shading points" render --help)

# Accelerator options: a value beyond the key's range is an error, never narrowed (2^32 + 2 -> 2).
set(T trace --scene cornell --rays ${WORK}/ok.rays --repeat 1)
expect(2 "option 'bins': 4294967298 is not in \\[2, 256\\]" ${T} --accel dacrt-rs --accel-opt bins=4294967298)
expect(2 "option 'samples': 4294967297 is not in" ${T} --accel dacrt --accel-opt samples=4294967297)
expect(2 "option 'delta_r': -1 is not in" ${T} --accel dacrt --accel-opt delta_r=-1)
expect(2 "option 'min_rays': -5 is not in" ${T} --accel dacrt-rs --accel-opt min_rays=-5)
expect(2 "option 'dir_res': 4294967300 is not in \\[1, 64\\]" ${T} --accel shafts --accel-opt dir_res=4294967300)
expect(2 "option 'max_list': 4294967297 is not in \\[1, 31\\]" ${T} --accel shafts --accel-opt max_list=4294967297)
expect(2 "option 'leaf_block': 4294967297 is not in \\[1, 15\\]" ${T} --accel bvh --accel-opt leaf_block=4294967297)
# An accelerator option's error names --accel-opt and the accelerator it was given to, whatever
# the command (it named only the key: "option 'bins': ...").
expect(2 "^rayscout: error: --accel-opt: accelerator 'dacrt-rs': option 'bins': 4294967298 is not in \\[2, 256\\]\n$"
       ${T} --accel dacrt-rs --accel-opt bins=4294967298)
expect(2 "^rayscout: error: --accel-opt: accelerator 'bvh': option 'bins' given twice" render --accel-opt bins=8
       --accel-opt bins=9 --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "^rayscout: error: --accel-opt: accelerator 'shafts' has no option\\(s\\): budgt \\(its options: bins, budget_mib, budget_rel, [a-z_, ]+\\)\n$" ${T} --accel shafts --accel-opt budgt=3)
expect(2 "^rayscout: error: --accel-opt: accelerator 'bvh': option '=8': expected key=value" ${T} --accel-opt =8)
# An unknown --accel is a usage error: it names the option and the command's help, as an
# unknown --integrator does.
expect(2 "^rayscout: error: --accel: unknown accelerator 'nope' \\(known: brute, [a-z0-9, -]+\\)\nRun 'rayscout [a-z]+ --help' for the options\\.\n$"
       ${T} --accel nope --accel-opt bins=8)
# Real-valued options are finite and, where they size memory, bounded (budget_rel=inf and
# budget_mib=1e30 used to build for ever).
expect(2 "option 'budget_rel': 'inf' is not a finite number" ${T} --accel shafts --accel-opt budget_rel=inf)
expect(2 "option 'budget_mib': 1e\\+30 is not in \\[0, 4096\\]" ${T} --accel shafts --accel-opt budget_mib=1e30)
expect(2 "option 'min_prob': 'nan' is not a finite number" ${T} --accel shafts-wide --accel-opt min_prob=nan)
# The grid addresses at most 2^32 shafts; the message names the options that size it.
expect(2 "shafts: a grid of [0-9x]+ voxels x 6144 direction cells is [0-9]+ shafts, more than 2\\^32; lower voxels or dir_res" ${T} --accel shafts --accel-opt voxels=1000000 --accel-opt dir_res=32)
expect(2 "option 'C_tri': 'inf' is not a finite number" ${T} --accel dacrt-rs --accel-opt C_tri=inf)
# "auto" is a value of the keys whose default it is; the wide BVH's collapse method and the
# shafts walk are separate keys (both used to be "collapse").
expect(0 "mrays_per_s" ${T} --accel shafts --accel-opt samples=auto --accel-opt reuse_rays=auto --accel-opt entry_boxes=auto --accel-opt walk_levels=2)
expect(0 "mrays_per_s" ${T} --accel shafts-wide --accel-opt collapse=greedy)
# diff of two images of different sizes names both files.
expect(0 "" render --width 8 --height 8 --out ${WORK}/a8.pfm)
expect(0 "" render --width 8 --height 6 --out ${WORK}/b6.pfm)
expect(2 "a8\\.pfm and .*b6\\.pfm: images differ in size: 8x8 vs 8x6" diff ${WORK}/a8.pfm ${WORK}/b6.pfm)
# A NaN pixel (a 1x1 PFM of NaN) fails --max-rmse and is drawn red, not read out of the
# colour ramp with int(NaN); a NaN scale is refused.
execute_process(COMMAND printf "PF\\n1 1\\n-1.0\\n\\000\\000\\300\\177\\000\\000\\300\\177\\000\\000\\300\\177"
                OUTPUT_FILE ${WORK}/nan1.pfm)
expect(0 "" render --width 1 --height 1 --out ${WORK}/ref1.pfm)
expect(1 "nonfinite 3 channel values.*not a number: fails --max-rmse" diff ${WORK}/nan1.pfm ${WORK}/ref1.pfm --max-rmse 0.01)
expect(0 "wrote" diff ${WORK}/nan1.pfm ${WORK}/ref1.pfm --out ${WORK}/nan-diff.png)
expect(2 "--scale: 'nan' is not a number" diff ${WORK}/a8.pfm ${WORK}/a8.pfm --scale nan)
# A PNG holds clamped 8-bit sRGB: against a float image the metrics measure the clamping too.
expect(0 "" render --width 8 --height 8 --out ${WORK}/a8.png)
expect(0 "warning: .*a8\\.png is a PNG \\(8-bit sRGB, clamped to \\[0, 1\\]\\) and .*a8\\.pfm is not"
       diff ${WORK}/a8.png ${WORK}/a8.pfm)
expect_without(0 "rmse" "warning" diff ${WORK}/a8.png ${WORK}/a8.png)
# The metrics of a grey 0.5 pixel against a black reference, by hand: RMSE and max 0.5, PSNR
# 10 log10(1 / 0.25) = 6.02 dB, relative MSE 0.25 / (0 + 0.01) = 25 (0.96 if A were the
# reference); --max-rmse fails above the RMSE only.
execute_process(COMMAND printf "PF\\n1 1\\n-1.0\\n\\000\\000\\000\\077\\000\\000\\000\\077\\000\\000\\000\\077"
                OUTPUT_FILE ${WORK}/half1.pfm)
execute_process(COMMAND printf "PF\\n1 1\\n-1.0\\n\\000\\000\\000\\000\\000\\000\\000\\000\\000\\000\\000\\000"
                OUTPUT_FILE ${WORK}/black1.pfm)
expect(0 "rmse +0\\.5\nrel_mse +25\npsnr +6\\.02 dB\nmax_abs +0\\.5\n" diff ${WORK}/half1.pfm ${WORK}/black1.pfm)
expect(0 "rmse +0\\.5\n" diff ${WORK}/half1.pfm ${WORK}/black1.pfm --max-rmse 0.5)
expect(1 "rmse 0\\.5 is above --max-rmse 0\\.49" diff ${WORK}/half1.pfm ${WORK}/black1.pfm --max-rmse 0.49)
# Output paths are checked before any work: a missing folder, a directory, an unknown format.
expect(2 "folder .*no-such-dir does not exist" render --width 8 --height 8 --out ${WORK}/no-such-dir/x.png)
expect(2 "a8.pfm/x.png: .*a8.pfm is a file, not a folder" render --width 8 --height 8 --out ${WORK}/a8.pfm/x.png)
expect(2 "big.png: a PNG of 32768x21846 pixels is beyond stb's PNG writer" render --width 32768 --height 21846 --out ${WORK}/big.png)
expect(2 "is a directory" render --width 8 --height 8 --out ${WORK})
expect(2 "unknown image format '.bmp'" render --width 8 --height 8 --out ${WORK}/x.bmp)
# An image path's error names its option: render writes two images with manylight.
expect(2 "--skip-image .*s\\.bmp: unknown image format '.bmp'"
       render --integrator manylight --width 8 --height 8 --out ${WORK}/x.png --skip-image ${WORK}/s.bmp)
expect(2 "--skip-image .*: is a directory, not an image file"
       render --integrator manylight --width 8 --height 8 --out ${WORK}/x.png --skip-image ${WORK})
expect(2 "--out .*/noext: no file extension to tell the image format by \\(use \\.png, \\.exr or \\.pfm\\)" render --width 8 --height 8 --out ${WORK}/noext)
expect(2 "--out .*d\\.bmp: unknown image format '.bmp'" diff ${WORK}/a8.pfm ${WORK}/a8.pfm --out ${WORK}/d.bmp)
expect(2 "--stats .*no-such-dir/s.json: folder" render --width 8 --height 8 --out ${WORK}/x.png --stats ${WORK}/no-such-dir/s.json)
expect(2 "--out .*no-such-dir/r.rays: folder" rays --scene cornell --workload primary --width 8 --height 8 --out ${WORK}/no-such-dir/r.rays)
expect(2 "--out .*: is a directory" trace --scene cornell --rays ${WORK}/ok.rays --out ${WORK})
# A folder that exists but takes no files (/proc, even for root), and the probe of an existing
# output leaves it as it was when the command then fails.
expect(2 "/proc/rayscout-x.png: cannot open for writing: " render --width 8 --height 8 --out /proc/rayscout-x.png)
expect(2 "--out /proc/r.rays: cannot open for writing: " rays --scene cornell --workload primary --width 8 --height 8 --out /proc/r.rays)
file(WRITE ${WORK}/keep.png "not yet an image")
expect(2 "unknown accelerator 'nope'" render --accel nope --width 8 --height 8 --out ${WORK}/keep.png)
file(READ ${WORK}/keep.png kept)
if(NOT kept STREQUAL "not yet an image")
  message(FATAL_ERROR "the output path check changed an existing file: '${kept}'")
endif()
expect(2 "is a directory, not a ray file" trace --scene cornell --rays ${WORK})
# diff checks --out before it compares: nothing on stdout before the error.
expect(2 "^rayscout: error: .*no-such-dir does not exist" diff ${WORK}/a8.pfm ${WORK}/a8.pfm --out ${WORK}/no-such-dir/d.png)
# manylight's inputs are checked before the work: its memory, the log's format, the reference.
expect(2 "--vpls 4294967295 at ~100 bytes.*more than this machine" render --integrator manylight --vpls 4294967295 --width 8 --height 8 --out ${WORK}/x.png)
# Cluster pairs are counted as made: 600 and 300 clusters are rounded up to 1024 and 512 (the
# estimate used to count 180000 pairs at 16 bytes for 524288 pairs of ~40 bytes).
expect(2 "524288 cluster pairs \\(--shading-clusters x --vpl-clusters\\) at ~40 bytes.*more than this machine" render --integrator manylight --vpls 4294967295 --shading-clusters 600 --vpl-clusters 300 --width 64 --height 48 --out ${WORK}/x.png)
expect(2 "--rmse-log .*log.txt: the file name must end in .json or .csv" render --integrator manylight --rmse-log ${WORK}/log.txt --width 8 --height 8 --out ${WORK}/x.png)
expect(2 "--reference .*x.png: must be an .exr or .pfm image" render --integrator manylight --reference ${WORK}/x.png --width 8 --height 8 --out ${WORK}/y.png)
expect(2 "--reference .*none.exr: no such file" render --integrator manylight --reference ${WORK}/none.exr --width 8 --height 8 --out ${WORK}/y.png)
# A reference of another size, or not an image, is found before the scene (missing here) is read.
expect(2 "--reference .*b6\\.pfm: 8x6 but rendering 8x8" render --integrator manylight --scene ${WORK}/missing.obj
       --reference ${WORK}/b6.pfm --width 8 --height 8 --out ${WORK}/y.png)
file(WRITE ${WORK}/junk.pfm "PF\n8 8\n")
expect(2 "junk\\.pfm" render --integrator manylight --scene ${WORK}/missing.obj --reference ${WORK}/junk.pfm
       --width 8 --height 8 --out ${WORK}/y.png)
# Options of another integrator are not silently dropped.
expect(0 "manylight options given are ignored by --integrator direct" render --width 8 --height 8 --vpls 5 --out ${WORK}/x.png)
expect(0 "--ao-radius is ignored by --integrator path" render --integrator path --width 8 --height 8 --max-depth 2 --ao-radius 1 --out ${WORK}/x.png)
expect(0 "--count is ignored by --integrator manylight" render --integrator manylight --width 8 --height 8 --vpls 50 --count --out ${WORK}/x.png)
# A secondary workload of a camera that sees nothing is empty: said, not a silent file of 0 rays.
file(WRITE ${WORK}/away.json [=[{"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1]}],
  "lights": [{"type": "point", "position": [0.5, 3, 3], "intensity": 1}], "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 10]}}]=])
expect(0 "warning: no diffuse rays: every primary ray missed the scene" rays --scene ${WORK}/away.json --workload diffuse
       --width 8 --height 8 --out ${WORK}/away.rays)
expect(0 "--ao-radius is ignored by --workload shadow" rays --scene cornell --workload shadow --width 8 --height 8 --ao-radius 1 --out ${WORK}/s.rays)
# The scene loader's warnings are printed by every command that loads a scene: rays and trace
# said nothing of a material library not found or of dropped triangles (render and info did).
file(WRITE ${WORK}/nomtl.obj "mtllib nowhere.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n")
foreach(command "render --width 4 --height 4 --out ${WORK}/nomtl.png"
                "rays --workload primary --width 4 --height 4 --out ${WORK}/nomtl.rays"
                "trace --rays ${WORK}/nomtl.rays --repeat 1")
  separate_arguments(args UNIX_COMMAND "${command}")
  expect(0 "rayscout: warning: .*nomtl\\.obj.*material library 'nowhere\\.mtl' not found" ${args} --scene ${WORK}/nomtl.obj)
endforeach()
# Primary rays need no tracing: no accelerator is built for them (it was, and never used), and
# an --accel given is said to be ignored. On a terminal the progress line shows no build.
expect(0 "warning: --accel is ignored by --workload primary" rays --scene cornell --workload primary --accel bvh2
       --width 8 --height 8 --out ${WORK}/p.rays)
expect_without(0 "wrote 64 primary rays" "warning" rays --scene cornell --workload primary --width 8 --height 8 --out ${WORK}/p.rays)
expect_without(0 "wrote 64 diffuse rays" "warning" rays --scene cornell --workload diffuse --accel bvh2 --width 8 --height 8 --out ${WORK}/p.rays)
# The log's format is read from its extension in any case, as an image's is (log.CSV was refused).
expect(0 "wrote" render --integrator manylight --width 8 --height 8 --vpls 20 --passes 2 --rmse-log ${WORK}/log.CSV
       --out ${WORK}/x.pfm)
file(STRINGS ${WORK}/log.CSV log_lines)
list(LENGTH log_lines log_count)
if(NOT log_count EQUAL 3)
  message(FATAL_ERROR "--rmse-log log.CSV holds ${log_count} lines, expected a header and 2 passes")
endif()
expect(0 "--rmse-log without --reference logs passes and skip rates only" render --integrator manylight --width 8 --height 8 --vpls 20 --passes 1 --rmse-log ${WORK}/log.csv --out ${WORK}/x.pfm)
# --count prints the work per ray even without --stats (64 camera and 64 AO rays).
expect(0 "work: 128 rays, per ray [0-9.]+ traversal steps, [0-9.]+ ray-box tests, [0-9.]+ ray-triangle tests" render --integrator ao --ao-samples 1 --width 8 --height 8 --spp 1 --count --out ${WORK}/x.png)
# Manylight options the chosen run does not read are reported, not dropped silently; so are
# costs under which skipping saves nothing (every mode then traces every sample, as exact).
set(M ${R} --integrator manylight --vpls 20)
expect(0 "--passes is ignored with --time-budget" ${M} --time-budget 0.01 --passes 3)
expect(0 "--epsilon is ignored by --visibility veach" ${M} --passes 1 --visibility veach --epsilon 0.2)
expect(0 "--costs is ignored by --visibility exact" ${M} --passes 1 --visibility exact --costs 0.7,0.25)
expect(0 "--costs 0.25,0.7: a sample costs no more with its shadow ray than without it: skipping saves nothing"
       ${M} --passes 1 --costs 0.25,0.7)
expect_without(0 "wrote" "warning" ${M} --passes 1 --costs 0.7,0.25 --epsilon 0.2 --cpu-clock)
expect(0 "--costs 0.5,0.5: a sample costs no more with its shadow ray" ${M} --passes 1 --costs 0.5,0.5)
expect_without(0 "wrote" "warning" ${M} --time-budget 0.01 --visibility conservative --costs 0.7,0.25)
# Manylight costs: two positive numbers; given, the skipping modes are repeatable (no timing in
# the skip probabilities), so two runs with the same seed write the same bytes.
expect(2 "--costs: At least 2 required" ${R} --integrator manylight --costs 0.5)
expect(2 "--costs: '-1' is not a number >= 0.001" ${R} --integrator manylight --costs 0.5,-1)
set(ML render --integrator manylight --visibility proposed --vpls 2000 --passes 4 --width 24 --height 16 --threads 2 --costs 0.7,0.25)
expect(0 "t_eval 0.7 us, t_skip 0.25 us" ${ML} --out ${WORK}/ml1.pfm)
expect(0 "wrote" ${ML} --out ${WORK}/ml2.pfm)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/ml1.pfm ${WORK}/ml2.pfm RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "manylight proposed with --costs gave two different images for one seed")
endif()
# A write that fails only when the file is flushed or closed (a full disk: /dev/full) is an
# error, not "wrote" and exit 0.
if(EXISTS /dev/full)
  foreach(ext png pfm exr json csv rays)
    file(CREATE_LINK /dev/full ${WORK}/full.${ext} SYMBOLIC)
  endforeach()
  foreach(ext png pfm exr)
    expect(2 "image: cannot write .*full\\.${ext}" render --width 8 --height 8 --spp 1 --out ${WORK}/full.${ext})
  endforeach()
  expect(2 "--stats: cannot write .*full\\.json" render --width 8 --height 8 --out ${WORK}/x.png --stats ${WORK}/full.json)
  expect(2 "--rmse-log: cannot write .*full\\.csv" render --integrator manylight --width 8 --height 8 --vpls 20 --passes 1
         --out ${WORK}/x.pfm --rmse-log ${WORK}/full.csv)
  expect(2 "ray file: cannot write .*full\\.rays" rays --scene cornell --workload primary --width 8 --height 8
         --out ${WORK}/full.rays)
  expect(2 "image: cannot write .*full\\.png" diff ${WORK}/ml1.pfm ${WORK}/ml2.pfm --out ${WORK}/full.png)
endif()
# A write cut short (here by a 5 KB file size limit, SIGXFSZ ignored so that the write fails
# with EFBIG) leaves no file behind: a truncated image or ray file stayed, to pass for a whole one.
if(EXISTS /bin/sh)
  foreach(command "render --width 64 --height 64 --spp 1 --out ${WORK}/cut-short.pfm"
                  "rays --scene cornell --width 64 --height 64 --out ${WORK}/cut-short.rays")
    string(REGEX REPLACE ".* --out " "" written "${command}")
    file(REMOVE ${written})
    separate_arguments(args UNIX_COMMAND "${command}")
    execute_process(COMMAND /bin/sh -c "trap '' XFSZ; ulimit -f 10 && exec \"$0\" \"$@\"" ${RAYSCOUT} ${args}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 2 OR NOT err MATCHES "cannot write .*cut-short.*File too large" OR EXISTS ${written})
      message(FATAL_ERROR "a write cut short (exit ${rc}) left ${written} behind or said no error:\n${out}${err}")
    endif()
    # Nor does it spoil the file it was to replace (it was truncated, then removed): the new one
    # is written beside it and renamed over it only once whole.
    file(WRITE ${written} "the previous run's output")
    execute_process(COMMAND /bin/sh -c "trap '' XFSZ; ulimit -f 10 && exec \"$0\" \"$@\"" ${RAYSCOUT} ${args}
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    file(READ ${written} kept)
    file(GLOB temporaries ${WORK}/.cut-short*)
    if(NOT rc EQUAL 2 OR NOT kept STREQUAL "the previous run's output" OR temporaries)
      message(FATAL_ERROR "a write cut short (exit ${rc}) spoilt ${written} or left ${temporaries}:\n${out}${err}")
    endif()
  endforeach()
endif()
# A scene whose only light is dark is refused when it is read (manylight made all-NaN pixels
# from it, exit 0, and the other integrators a black image).
file(WRITE ${WORK}/dark.json [=[{"meshes": [{"shape": "box", "min": [0, 0, 0], "max": [1, 1, 1]}],
  "lights": [{"type": "point", "position": [0.5, 0.5, 3], "intensity": 0}]}]=])
foreach(integrator manylight direct)
  expect(2 "dark\\.json: lights\\[0\\]\\.intensity: a point light must emit" render --scene ${WORK}/dark.json
         --integrator ${integrator} --width 4 --height 4 --vpls 10 --passes 1 --out ${WORK}/x.pfm)
endforeach()
# A scene lit only by area lights renders dark under the default integrator: say so.
file(WRITE ${WORK}/area-only.json [=[{"meshes": [{"shape": "box", "min": [-1, -1, -1], "max": [1, 1, 1]}],
  "lights": [{"type": "area", "center": [0, 3, 0], "normal": [0, -1, 0], "size": 1, "emission": 10}]}]=])
expect(0 "direct lights with point lights only.*2 emissive triangles" render --scene ${WORK}/area-only.json
       --width 8 --height 8 --out ${WORK}/x.png)
# Radiance beyond the float range gives inf pixels: said, not passed off as a bright image.
file(WRITE ${WORK}/hot.json [=[{"meshes": [{"shape": "quad", "corner": [-5, -5, 0], "edge1": [10, 0, 0], "edge2": [0, 10, 0]}],
  "lights": [{"type": "area", "center": [0, 0, 1], "normal": [0, 0, -1], "size": 10, "emission": 3e38}],
  "camera": {"eye": [0, -3, 0.5], "look_at": [0, 0, 0], "up": [0, 0, 1]}}]=])
expect(0 "warning: [0-9]+ of 64 pixels are not finite" render --scene ${WORK}/hot.json --integrator area
       --width 8 --height 8 --spp 1 --out ${WORK}/x.pfm)
# An output that names an input, or another output, is refused before any work: it would
# destroy the input (`trace --out` over its --rays left HITS data there) or one of the outputs.
expect(0 "wrote" rays --scene cornell --workload primary --width 4 --height 4 --out ${WORK}/in.rays)
expect(2 "--out .*in\\.rays: is also the input --rays .*in\\.rays, which would be overwritten"
       trace --scene cornell --rays ${WORK}/in.rays --repeat 1 --out ${WORK}/in.rays)
expect(2 "--stats .*same\\.png: is also the output --out .*/\\./same\\.png"
       render --width 8 --height 8 --out ${WORK}/./same.png --stats ${WORK}/same.png)
expect(2 "--out .*ml1\\.pfm: is also the input --reference .*ml1\\.pfm"
       ${ML} --reference ${WORK}/ml1.pfm --out ${WORK}/ml1.pfm)
expect(2 "--out .*ml1\\.pfm: is also image A" diff ${WORK}/ml1.pfm ${WORK}/ml2.pfm --out ${WORK}/ml1.pfm)
# An output path that is a dangling symbolic link is written through the link.
file(REMOVE ${WORK}/link-target.png)
file(CREATE_LINK ${WORK}/link-target.png ${WORK}/dangling.png SYMBOLIC)
expect(0 "wrote" render --width 8 --height 8 --spp 1 --out ${WORK}/dangling.png)
if(NOT EXISTS ${WORK}/link-target.png)
  message(FATAL_ERROR "render --out through a dangling link did not write the link's target")
endif()
# --stats -: stdout holds the JSON alone (the summary lines go to stderr), so it can be parsed.
execute_process(COMMAND ${RAYSCOUT} render --width 8 --height 6 --spp 1 --out ${WORK}/x.png --stats -
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(JSON json_height ERROR_VARIABLE json_error GET "${out}" height)
if(NOT rc EQUAL 0 OR json_error OR NOT json_height EQUAL 6 OR NOT err MATCHES "wrote")
  message(FATAL_ERROR "render --stats -: stdout is not the JSON alone (exit ${rc}, ${json_error}):\n${out}\nstderr:\n${err}")
endif()
# A scene path that is not UTF-8 (Latin-1 "caf\xe9.obj") still gives valid --stats JSON: it made
# the JSON library throw after the image was written (exit 1, no stats).
string(ASCII 233 latin1_e)
file(WRITE "${WORK}/caf${latin1_e}.obj" "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
execute_process(COMMAND ${RAYSCOUT} render --scene "${WORK}/caf${latin1_e}.obj" --width 4 --height 4 --spp 1
                        --out ${WORK}/x.png --stats -
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(JSON json_width ERROR_VARIABLE json_error GET "${out}" width)
if(NOT rc EQUAL 0 OR json_error OR NOT json_width EQUAL 4)
  message(FATAL_ERROR "render --stats - of a Latin-1 scene path (exit ${rc}, ${json_error}):\n${out}\nstderr:\n${err}")
endif()
# Each --integrator name renders with that integrator (the JSON names the one that ran).
foreach(integrator direct area ao path manylight)
  execute_process(COMMAND ${RAYSCOUT} render --integrator ${integrator} --width 4 --height 4 --spp 1 --vpls 20 --passes 1
                          --out ${WORK}/i.pfm --stats -
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(JSON ran ERROR_VARIABLE json_error GET "${out}" integrator)
  if(NOT rc EQUAL 0 OR json_error OR NOT ran STREQUAL integrator)
    message(FATAL_ERROR "render --integrator ${integrator} ran '${ran}' (exit ${rc}, ${json_error}):\n${out}${err}")
  endif()
endforeach()
# Manylight's visibility samples are traced one cluster pair at a time: bounded.
expect(2 "--visibility-samples: '65537' is not an integer in \\[1, 65536\\]" ${ML} --visibility-samples 65537 --out ${WORK}/x.pfm)
# manylight renders through a pinhole: a scene's thin lens is said to be ignored.
file(WRITE ${WORK}/lens.json [=[{"meshes": [{"shape": "box", "min": [-1, -1, -1], "max": [1, 1, 1]}],
  "lights": [{"type": "point", "position": [0, 3, 3], "intensity": 10}],
  "camera": {"eye": [0, 0, 5], "look_at": [0, 0, 0], "lens_radius": 0.5}}]=])
expect(0 "manylight renders through a pinhole: the camera's lens_radius 0.5 \\(depth of field\\) is ignored"
       render --scene ${WORK}/lens.json --integrator manylight --width 8 --height 8 --vpls 20 --passes 1 --out ${WORK}/x.pfm)
# A tunable given twice is an error, as a repeated option is, not "the last one wins".
expect(2 "option 'bins' given twice \\('8' and '9'\\)" render --accel bvh --accel-opt bins=8 --accel-opt bins=9 --width 8 --height 8 --out ${WORK}/x.png)
# On a terminal, trace shows its progress on stderr (the timed runs of a slow accelerator on a
# big ray file take minutes); stdout keeps the one JSON line. `script` gives the command a
# terminal; without it this part is skipped.
find_program(SCRIPT script)
# Runs command on a terminal; its output must exit with code, match must and not match must_not.
function(on_terminal code must must_not what command)
  execute_process(COMMAND ${SCRIPT} -qec "${command}" /dev/null
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL code OR NOT out MATCHES "${must}" OR (NOT must_not STREQUAL "" AND out MATCHES "${must_not}"))
    message(FATAL_ERROR "${what} on a terminal (exit ${rc}):\n${out}${err}")
  endif()
endfunction()
if(SCRIPT)
  on_terminal(0 "trace: built in [0-9.]+ s.*run 3/3.*counting run.*\"mrays_per_s\"" ""
              "trace shows no progress" "${RAYSCOUT} trace --scene cornell --rays ${WORK}/ok.rays --repeat 3 --count")
  on_terminal(0 "rays: building bvh over 32 triangles.*rays: making the diffuse rays of 8x8 pixels at 1 spp.*wrote" ""
              "rays shows no progress"
              "${RAYSCOUT} rays --scene cornell --workload diffuse --width 8 --height 8 --out ${WORK}/bar.rays")
  on_terminal(0 "rays: making the primary rays of 8x8 pixels at 1 spp.*wrote" "building" "rays --workload primary builds"
              "${RAYSCOUT} rays --scene cornell --workload primary --width 8 --height 8 --out ${WORK}/bar.rays")
  # The progress line is cleared when the work ends, and before an error message, which then
  # starts the line (a script running trace per ray set keeps a clean terminal).
  on_terminal(2 "loading the rays[^\r]*\r.\\[Krayscout: error: .*cut\\.rays" ""
              "trace: the error does not start a cleared line" "${RAYSCOUT} trace --scene cornell --rays ${WORK}/cut.rays")
  # manylight ends the line itself before its summary: no empty line follows it.
  on_terminal(0 "pass 2/2" "\n\r?\n" "render --integrator manylight prints an empty line"
              "${RAYSCOUT} render --integrator manylight --width 8 --height 8 --vpls 20 --passes 2 --out ${WORK}/bar.png")
  # render's time left comes from whole passes: none during the first (a single-pass direct
  # render of a scene without mirrors ended at "~3 s left" for 1 s of work: its bounce 0 was
  # counted as a quarter of the pass), then one for each later pass.
  on_terminal(0 "render: loading the scene.*render: building bvh over 32 triangles.*pass 4/4[^\r]*~[0-9.]+ s left"
              "pass 1/4[^\r]*left" "render's progress"
              "${RAYSCOUT} render --integrator path --width 32 --height 32 --spp 4 --max-batch 1024 --out ${WORK}/bar.png")
  # --max-depth takes any int: the bar's share of a pass per bounce overflowed at INT_MAX
  # (undefined; the sanitizer build stops on it).
  on_terminal(0 "bounce 0/2147483647" "" "render's progress at --max-depth 2147483647"
              "${RAYSCOUT} render --integrator path --width 8 --height 8 --max-depth 2147483647 --out ${WORK}/bar.png")
  execute_process(COMMAND ${RAYSCOUT} trace --scene cornell --rays ${WORK}/ok.rays --repeat 3
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT err STREQUAL "")
    message(FATAL_ERROR "trace without a terminal writes progress to stderr (exit ${rc}):\n${err}")
  endif()
endif()
# Out of memory, a command names what to lower among its own options (trace used to advise
# render's --width, --spp and --vpls). A RAYS and a HITS header claiming 8M records, followed by
# a sparse body, ask for 256 MB and 128 MB under a 200 MB address-space limit; --threads 1 keeps
# the worker threads' stacks out of it. Sanitizers reserve terabytes of address space: skipped.
if(NOT SANITIZE AND EXISTS /bin/sh)
  execute_process(COMMAND /usr/bin/python3 -c "import struct,sys
for path, kind, size in ((sys.argv[2], b'RAYS', 32), (sys.argv[3], b'HITS', 16)):
    f = open(path, 'wb'); f.write(kind + open(sys.argv[1], 'rb').read(16)[4:8] + struct.pack('<Q', 8 << 20))
    f.truncate(16 + size * (8 << 20))" ${WORK}/ok.rays ${WORK}/huge.rays ${WORK}/huge.hits RESULT_VARIABLE rc)
  execute_process(COMMAND /bin/sh -c "ulimit -v 200000 && exec \"$0\" \"$@\"" ${RAYSCOUT} trace --threads 1 --scene cornell
                          --rays ${WORK}/huge.rays RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 1 OR NOT err MATCHES "out of memory \\(trace fewer rays" OR err MATCHES "--vpls")
    message(FATAL_ERROR "trace out of memory (exit ${rc}):\n${out}${err}")
  endif()
  execute_process(COMMAND /bin/sh -c "ulimit -v 200000 && exec \"$0\" \"$@\"" ${RAYSCOUT} compare-hits
                          ${WORK}/huge.hits ${WORK}/huge.hits RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 1 OR NOT err MATCHES "out of memory \\(compare smaller files" OR err MATCHES "--vpls")
    message(FATAL_ERROR "compare-hits out of memory (exit ${rc}):\n${out}${err}")
  endif()
  file(REMOVE ${WORK}/huge.rays ${WORK}/huge.hits)
endif()
