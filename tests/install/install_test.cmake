# cmake --install into WORK/prefix, then configure, build and run consumer/ against it with
# the build's compiler, flags and configuration. WORK is removed at the end, pass or fail.
# Run by CTest (tests/install/CMakeLists.txt): cmake -DBUILD_DIR=... -DWORK=... -P install_test.cmake
set(prefix ${WORK}/prefix)
function(fail message)
  file(REMOVE_RECURSE ${WORK})
  message(FATAL_ERROR "${message}")
endfunction()
# run(<what> <command...>): runs it, fails naming <what> with its output unless it exits 0.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    fail("${what} failed (${rc}): ${ARGN}\n${out}${err}")
  endif()
  set(output "${out}${err}" PARENT_SCOPE)
endfunction()
function(expect_match what pattern text)
  if(NOT "${text}" MATCHES "${pattern}")
    fail("${what}: output does not match '${pattern}':\n${text}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK})
run("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})

# The installed package names neither the source nor the build tree (e.g. src/ through
# rayscout::core_private, or include/ without $<INSTALL_INTERFACE>).
file(GLOB package_files ${prefix}/lib*/cmake/rayscout/*.cmake)
if(NOT package_files)
  fail("no package files in ${prefix}/lib*/cmake/rayscout")
endif()
foreach(file IN LISTS package_files)
  file(READ ${file} text)
  foreach(tree ${SOURCE_DIR} ${BUILD_DIR})
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      fail("${file} names ${tree}")
    endif()
  endforeach()
endforeach()

# Shared libraries: the installed CLI finds them by its RUNPATH, in the prefix, not the build tree.
unset(ENV{LD_LIBRARY_PATH})
run("installed CLI" ${prefix}/bin/rayscout --version)
expect_match("installed CLI" "^rayscout ${VERSION}" "${output}")
if(SHARED)
  file(GLOB libraries ${prefix}/lib*/librayscout_core.so.${VERSION})
  if(NOT libraries)
    fail("no ${prefix}/lib*/librayscout_core.so.${VERSION} (VERSION and SOVERSION)")
  endif()
  file(GET_RUNTIME_DEPENDENCIES EXECUTABLES ${prefix}/bin/rayscout RESOLVED_DEPENDENCIES_VAR resolved
       UNRESOLVED_DEPENDENCIES_VAR unresolved)
  list(FILTER resolved INCLUDE REGEX "/librayscout_[a-z]+\\.so")
  if(unresolved OR NOT resolved)
    fail("installed CLI: unresolved ${unresolved}, rayscout libraries ${resolved}")
  endif()
  foreach(library IN LISTS resolved)
    string(FIND "${library}" "${prefix}/" at)
    if(NOT at EQUAL 0)
      fail("installed CLI loads ${library}, outside ${prefix}")
    endif()
  endforeach()
endif()

# Sanitized libraries: the consumer is compiled the same way (the package adds the link flag).
set(flags "${CXX_FLAGS}")
if(SANITIZE)
  string(APPEND flags " -fsanitize=${SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all")
endif()
run("consumer configure" ${CMAKE_COMMAND} -S ${CONSUMER} -B ${WORK}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${CONFIG}
    -DCMAKE_CXX_FLAGS=${flags} -DRAYSCOUT_VERSION=${VERSION})
# Found in the prefix (not the build tree), and it says how the libraries were built.
string(REGEX MATCH "rayscout_DIR=[^\n]*" found "${output}")
string(FIND "${found}" "rayscout_DIR=${prefix}/" at)
if(NOT at EQUAL 0)
  fail("consumer found the package elsewhere: ${found}\n${output}")
endif()
if(NATIVE)
  set(native ON)
else()
  set(native OFF)
endif()
expect_match("consumer configure" "rayscout_NATIVE=${native} " "${output}")

run("consumer build" ${CMAKE_COMMAND} --build ${WORK}/build --config ${CONFIG})
set(consumer ${WORK}/build/consumer)
if(NOT EXISTS ${consumer})  # a multi-config generator's folder
  set(consumer ${WORK}/build/${CONFIG}/consumer)
endif()
run("consumer" ${consumer} ${WORK}/out.exr)
# README's camera ray on the built-in Cornell box meets the tall box (triangles 20-29) at the
# same triangle and distance as in the tree (tests/apps/library_use_test.cpp).
expect_match("consumer" "^triangles 32\nhit 28 t 1\\.025642\nrendered 8x8\nvisibility proposed\n$" "${output}")
if(NOT EXISTS ${WORK}/out.exr)
  fail("consumer wrote no ${WORK}/out.exr")
endif()
file(REMOVE_RECURSE ${WORK})
