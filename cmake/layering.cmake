# The layering of docs/architecture.md as a build rule: which stage's files may include which.
# A stage is a folder of include/caliper/ and src/ (plus "top" for avatar.h and the avatar
# report, and "base" for the headers every stage may use). A file may include its own stage,
# vocabulary, base and the stages listed here; any other `#include "caliper/…"` fails the build
# (checked at configure time and again whenever a stage's files change: CMakeLists.txt).
#
# Used two ways: include()d by CMakeLists.txt, and as a script,
#   cmake -DCALIPER_ROOT=<tree> -DCALIPER_STAGE=<stage> -P cmake/layering.cmake
# which checks one stage of the tree at CALIPER_ROOT (the build's check and its tests do this),
# or every stage with -DCALIPER_CHECK_ALL=ON instead of CALIPER_STAGE.

if(CMAKE_SCRIPT_MODE_FILE)
  cmake_minimum_required(VERSION 3.20)  # policies (IN_LIST) when run as a script
endif()

# stage → the other stages it may include. Order: bottom to top.
set(CALIPER_LAYERS
  "vocabulary:"
  "body:"
  "measure:body"
  "io:body,measure"
  "protocol:measure"
  "capture:protocol,measure"
  "regress:body,measure"
  "export:body"
  "mannequin:body,measure,io,protocol"
  "makehuman:body,measure,io,mannequin"
  "top:body,measure,regress,protocol,export"
  "evaluation:top,body,measure,regress,protocol,io,mannequin")

# Every stage, base (errors.h and the like, below everything) first.
set(CALIPER_STAGES base)
foreach(entry IN LISTS CALIPER_LAYERS)
  string(REGEX REPLACE ":.*" "" name "${entry}")
  list(APPEND CALIPER_STAGES ${name})
endforeach()

# The top-level headers each stage may use, and the stage of the other top-level files.
set(CALIPER_BASE_HEADERS errors.h utf8.h private_files.h random.h)
set(CALIPER_TOP_HEADERS avatar.h avatar_report.h avatar_weight_change.h)

# The files of a stage, relative to `root`.
function(caliper_stage_files root stage out)
  if(stage STREQUAL "top")
    set(patterns include/caliper/avatar*.h src/avatar*.cpp)
  elseif(stage STREQUAL "base")
    set(patterns include/caliper/errors.h include/caliper/utf8.h include/caliper/private_files.h
      include/caliper/random.h include/caliper/detail/*.h src/*.h src/errors.cpp src/utf8.cpp
      src/private_files.cpp src/json_read.cpp src/csv_table.cpp)
  else()
    set(patterns include/caliper/${stage}/*.h src/${stage}/*.h src/${stage}/*.cpp)
  endif()
  set(files)
  foreach(p IN LISTS patterns)
    if(CMAKE_SCRIPT_MODE_FILE)
      file(GLOB found "${root}/${p}")
    else()
      file(GLOB found CONFIGURE_DEPENDS "${root}/${p}")  # a new file re-runs the configure step
    endif()
    list(APPEND files ${found})
  endforeach()
  set(${out} ${files} PARENT_SCOPE)
endfunction()

# The stage an include names: "caliper/body/mesh.h" → body, "caliper/errors.h" → base.
function(caliper_included_stage path out)
  if(path MATCHES "^caliper/detail/")
    set(${out} base PARENT_SCOPE)
  elseif(path MATCHES "^caliper/([a-z_]+)/")
    set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
  else()
    string(REGEX REPLACE "^caliper/" "" name "${path}")
    if(name IN_LIST CALIPER_BASE_HEADERS)
      set(${out} base PARENT_SCOPE)
    elseif(name IN_LIST CALIPER_TOP_HEADERS)
      set(${out} top PARENT_SCOPE)
    else()
      set(${out} "umbrella (${name})" PARENT_SCOPE)  # caliper.h: for the apps only
    endif()
  endif()
endfunction()

# Checks every file of `stage` under `root`; stops with FATAL_ERROR listing each forbidden include.
function(caliper_check_stage root stage)
  set(allowed ${stage} vocabulary base)
  set(known FALSE)
  foreach(entry IN LISTS CALIPER_LAYERS)
    string(REPLACE ":" ";" parts "${entry}")
    list(GET parts 0 name)
    if(name STREQUAL stage)
      set(known TRUE)
      list(LENGTH parts n)
      if(n GREATER 1)
        list(GET parts 1 deps)
        string(REPLACE "," ";" deps "${deps}")
        list(APPEND allowed ${deps})
      endif()
    endif()
  endforeach()
  if(stage STREQUAL "base")
    set(allowed base)
  elseif(NOT known)
    message(FATAL_ERROR "layering: unknown stage '${stage}' (cmake/layering.cmake)")
  endif()
  caliper_stage_files("${root}" ${stage} files)
  set(problems)
  foreach(f IN LISTS files)
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"caliper/")
    foreach(line IN LISTS lines)
      string(REGEX MATCH "\"(caliper/[^\"]+)\"" _ "${line}")
      caliper_included_stage("${CMAKE_MATCH_1}" target)
      if(NOT target IN_LIST allowed)
        file(RELATIVE_PATH rel "${root}" "${f}")
        list(APPEND problems "  ${rel}: ${stage} may not include ${CMAKE_MATCH_1} (${target})")
      endif()
    endforeach()
  endforeach()
  if(problems)
    list(JOIN allowed ", " allowed_text)
    string(REPLACE ";" "\n" problems "${problems}")
    message(FATAL_ERROR "layering (docs/architecture.md): ${stage} may include only ${allowed_text}:\n${problems}")
  endif()
endfunction()

# Stops unless every source file under root/src belongs to a stage (else it would not be built).
function(caliper_check_every_source_has_a_stage root)
  file(GLOB_RECURSE all CONFIGURE_DEPENDS "${root}/src/*.cpp")
  foreach(stage IN LISTS CALIPER_STAGES)
    caliper_stage_files("${root}" ${stage} files)
    list(REMOVE_ITEM all ${files})
  endforeach()
  if(all)
    message(FATAL_ERROR "layering: these sources belong to no stage (cmake/layering.cmake): ${all}")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED CALIPER_STAGE)
  caliper_check_stage("${CALIPER_ROOT}" "${CALIPER_STAGE}")
elseif(CMAKE_SCRIPT_MODE_FILE AND CALIPER_CHECK_ALL)
  foreach(stage IN LISTS CALIPER_STAGES)
    caliper_check_stage("${CALIPER_ROOT}" ${stage})
  endforeach()
endif()
