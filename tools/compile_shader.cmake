# Compiles one GLSL shader to SPIR-V, optimises it and embeds it as a C++
# array (run by the build: CMakeLists.txt, whitted_add_shader).
#
#   cmake -DGLSLANG=… -DSPIRV_OPT=… [-DOPT_FLAGS=-O] -DSOURCE=x.comp -DHEADER=out.h
#         -DVARIABLE=kName -DINCLUDE=dir [-DDEFINES=-DA;-DB] -P tools/compile_shader.cmake
#
# Why spirv-opt: glslang's SPIR-V keeps every GLSL function a function.
# Lavapipe turns it into NIR and inlines and optimises it each time a
# pipeline is created (its pipeline cache keeps none of that); from SPIR-V
# with the functions already inlined, lavapipe creates the tracer's
# pipeline sooner, and the render is as fast and the image the same.
# spirv-opt -O shortens the pipeline time further but its code renders
# slower on lavapipe (measured: see tools/benchmark_results/README.md).
# SPIRV_OPT empty: the SPIR-V is embedded as glslang wrote it.
foreach(var GLSLANG SOURCE HEADER VARIABLE INCLUDE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "compile_shader.cmake: ${var} is not set")
  endif()
endforeach()
if(NOT DEFINED OPT_FLAGS)
  set(OPT_FLAGS --inline-entry-points-exhaustive --eliminate-dead-functions)
endif()

set(spv ${HEADER}.spv)
execute_process(
  COMMAND ${GLSLANG} -V --target-env vulkan1.2 --quiet ${DEFINES} -I${INCLUDE} --depfile ${HEADER}.d
          -o ${spv} ${SOURCE}
  RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "glslang failed on ${SOURCE}")
endif()
# glslang's depfile names the file it wrote; the build's target is the header.
file(READ ${HEADER}.d depends)
string(REPLACE "${spv}:" "${HEADER}:" depends "${depends}")
file(WRITE ${HEADER}.d "${depends}")

if(SPIRV_OPT)
  # Its warnings name the functions it leaves alone (those with an early
  # return; lavapipe inlines them): shown only if it fails.
  execute_process(COMMAND ${SPIRV_OPT} ${OPT_FLAGS} --target-env=vulkan1.2 ${spv} -o ${spv}.opt
                  RESULT_VARIABLE status OUTPUT_VARIABLE said ERROR_VARIABLE said)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "spirv-opt failed on ${SOURCE}:\n${said}")
  endif()
  file(RENAME ${spv}.opt ${spv})
endif()

# SPIR-V words are little-endian in the file: bytes 0 1 2 3 make 0x33221100.
file(READ ${spv} bytes HEX)
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1," words "${bytes}")
# Eight words a line (CMake's regular expressions have no {n}).
set(word "0x........,")
string(REGEX REPLACE "(${word}${word}${word}${word}${word}${word}${word}${word})" "\\1\n\t" words "${words}")
file(WRITE ${HEADER}.tmp "// ${SOURCE} (tools/compile_shader.cmake)\n#pragma once\n#include <cstdint>\n"
                          "inline constexpr uint32_t ${VARIABLE}[] = {\n\t${words}\n};\n")
file(RENAME ${HEADER}.tmp ${HEADER})
