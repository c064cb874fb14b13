# Issue 43: no include arrow runs back up. Every source file has a layer, and a file includes
# only files of its own layer or of one below it:
#
#   the core, in its own order   core < sensors, hydraulics, drives < cutting < dynamics, design
#                                < control
#   the host                     sim < io (the scenario's reader and the formats)
#   one system's folder          its settings (what its HAL component links) < its check
#                                (validate.cpp, the rig it probes) < the rest (study, metrics, ...)
#   every system                 src/systems/*.{hpp,cpp}: the registry, the runner, the estimate
#   the optimiser                src/optimize
#   the programs                 apps/, hal/
#
# A header's layer is its source's (x.hpp is where x.cpp is; a system's library is read from its
# folder's lathectl_system() call); in a system's folder a header without a source (types alone:
# rig_config.hpp, entry.hpp) is at the folder's bottom, and what it includes is checked. tests/,
# bench/ and fuzz/ may include anything. A core folder not in the order above is an error: place
# it. cmake -DSOURCE_DIR=<tree> -P layer_order.cmake; fails naming each file:line, the include
# and both layers.
cmake_minimum_required(VERSION 3.25)

set(core_rank_core 0)
set(core_rank_sensors 1)
set(core_rank_hydraulics 1)
set(core_rank_drives 1)
set(core_rank_cutting 2)
set(core_rank_dynamics 3)
set(core_rank_design 3)
set(core_rank_control 4)
set(rank_sim 10)
set(rank_io 11)
set(rank_settings 20)
set(rank_check 21)
set(rank_system 22)
set(rank_systems 23)
set(rank_optimize 30)
set(rank_programs 40)

# The library of each source of a system folder: lib_<folder>_<stem> = settings|check|system.
file(GLOB system_dirs LIST_DIRECTORIES true ${SOURCE_DIR}/src/systems/*)
foreach(dir ${system_dirs})
  if(NOT EXISTS ${dir}/CMakeLists.txt)
    continue()
  endif()
  get_filename_component(folder ${dir} NAME)
  file(READ ${dir}/CMakeLists.txt text)
  string(REGEX REPLACE "#[^\n]*" "" text "${text}")
  string(REGEX MATCH "lathectl_system\\(([^)]*)\\)" call "${text}")
  string(REGEX REPLACE "[ \t\r\n]+" ";" words "${CMAKE_MATCH_1}")
  set(lib "")
  foreach(w ${words})
    if(w STREQUAL "SETTINGS")
      set(lib settings)
    elseif(w STREQUAL "CHECK")
      set(lib check)
    elseif(w STREQUAL "SOURCES")
      set(lib system)
    elseif(w MATCHES "^(.*)\\.cpp$" AND lib)
      set(lib_${folder}_${CMAKE_MATCH_1} ${lib})
    endif()
  endforeach()
endforeach()

# layer_of(<path relative to SOURCE_DIR> <out rank> <out name>): rank -1 when unranked.
function(layer_of rel out_rank out_name)
  set(rank -1)
  set(name "")
  set(folder "")
  if(rel MATCHES "^include/lathectl/([^/]+)/")  # (if() does not stop at a true OR operand)
    set(folder ${CMAKE_MATCH_1})
  elseif(rel MATCHES "^src/([^/]+)/")
    set(folder ${CMAKE_MATCH_1})
  endif()
  if(folder)
    if(folder STREQUAL "sim" OR folder STREQUAL "io")
      set(rank ${rank_${folder}})
      set(name ${folder})
    elseif(folder STREQUAL "optimize")
      set(rank ${rank_optimize})
      set(name optimize)
    elseif(folder STREQUAL "systems")
      if(rel MATCHES "^src/systems/([^/]+)/([^/]+)\\.(hpp|cpp)$")
        set(sys ${CMAKE_MATCH_1})
        set(stem ${CMAKE_MATCH_2})
        if(DEFINED lib_${sys}_${stem})
          set(lib ${lib_${sys}_${stem}})
        elseif(stem STREQUAL "study_phases")  # the study's private header (study*.cpp)
          set(lib system)
        else()  # a header of types alone: the folder's bottom, its own includes checked
          set(lib settings)
        endif()
        set(rank ${rank_${lib}})
        set(name "${sys} ${lib}")
      else()
        set(rank ${rank_systems})
        set(name "systems (every system)")
      endif()
    elseif(DEFINED core_rank_${folder})
      set(rank ${core_rank_${folder}})
      set(name "core/${folder}")
    else()
      message(SEND_ERROR "${rel}: the core folder ${folder} has no place in the order "
                         "(tests/layers/layer_order.cmake)")
    endif()
  elseif(rel MATCHES "^(apps|hal)/")
    set(rank ${rank_programs})
    set(name ${CMAKE_MATCH_1})
  endif()
  set(${out_rank} ${rank} PARENT_SCOPE)
  set(${out_name} "${name}" PARENT_SCOPE)
endfunction()

# Arrows up that are known and not yet turned round, "file|include", each with its fix. The test
# fails on any other, and on one listed here that is gone (take it off the list).
#   a system's settings.hpp (and A's and B's machine_params.hpp) includes its rig.hpp for
#   RigConfig, which the settings hold: the config belongs to the settings layer (a
#   rig_config.hpp, as C's and E's); B's machine
#   file's types and reader (the settings library: lobes_input.cpp, lobes_cost.cpp,
#   lobes_system.cpp) are declared in lobes.hpp beside the lobe computation (lobes.cpp): their
#   half of it belongs to the settings layer (a lobes_input.hpp).
set(known_up
  "src/systems/a_pulse_feed/settings.hpp|systems/a_pulse_feed/rig.hpp"
  "src/systems/b_chatter/settings.hpp|systems/b_chatter/rig.hpp"
  "src/systems/d_gauging/settings.hpp|systems/d_gauging/rig.hpp"
  "src/systems/a_pulse_feed/machine_params.hpp|systems/a_pulse_feed/rig.hpp"
  "src/systems/b_chatter/machine_params.hpp|systems/b_chatter/rig.hpp"
  "src/systems/b_chatter/lobes_cost.cpp|systems/b_chatter/lobes.hpp"
  "src/systems/b_chatter/lobes_input.cpp|systems/b_chatter/lobes.hpp"
  "src/systems/b_chatter/lobes_system.cpp|systems/b_chatter/lobes.hpp"
  "src/systems/b_chatter/settings.cpp|systems/b_chatter/lobes.hpp")
set(known_seen "")

file(GLOB_RECURSE files ${SOURCE_DIR}/include/*.hpp ${SOURCE_DIR}/src/*.hpp
     ${SOURCE_DIR}/src/*.cpp ${SOURCE_DIR}/apps/*.hpp ${SOURCE_DIR}/apps/*.cpp
     ${SOURCE_DIR}/hal/*.hpp ${SOURCE_DIR}/hal/*.cpp)
if(NOT files)
  message(FATAL_ERROR "no sources under ${SOURCE_DIR}")
endif()
set(offences 0)
set(arrows 0)
foreach(f ${files})
  file(RELATIVE_PATH rel ${SOURCE_DIR} ${f})
  layer_of(${rel} from from_name)
  if(from LESS 0)
    continue()
  endif()
  get_filename_component(here ${f} DIRECTORY)
  file(STRINGS ${f} lines REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line ${lines})
    string(REGEX MATCH "\"([^\"]+)\"" _ "${line}")
    set(inc ${CMAKE_MATCH_1})
    set(target "")
    if(inc MATCHES "^lathectl/" AND EXISTS ${SOURCE_DIR}/include/${inc})
      set(target include/${inc})
    elseif(inc MATCHES "^(systems|optimize)/" AND EXISTS ${SOURCE_DIR}/src/${inc})
      set(target src/${inc})
    elseif(EXISTS ${here}/${inc})
      file(RELATIVE_PATH target ${SOURCE_DIR} ${here}/${inc})
    endif()
    if(NOT target)
      continue()
    endif()
    layer_of(${target} to to_name)
    math(EXPR arrows "${arrows} + 1")
    if(to GREATER from AND "${rel}|${inc}" IN_LIST known_up)
      list(APPEND known_seen "${rel}|${inc}")
    elseif(to GREATER from)
      message(SEND_ERROR "${rel}: ${from_name} includes ${to_name} above it: ${line}")
      math(EXPR offences "${offences} + 1")
    endif()
  endforeach()
endforeach()
if(EXISTS ${SOURCE_DIR}/src/systems)  # the real tree (not tests/layers/offending)
  foreach(k ${known_up})
    if(NOT k IN_LIST known_seen)
      message(SEND_ERROR "${k}: no longer an arrow up: take it off known_up")
      math(EXPR offences "${offences} + 1")
    endif()
  endforeach()
endif()
list(LENGTH known_seen n_known)
list(LENGTH files n_files)
if(offences GREATER 0)
  message(FATAL_ERROR "${offences} include(s) up a layer (of ${arrows} in ${n_files} files)")
endif()
message(STATUS "${arrows} includes in ${n_files} files: none runs up a layer but the "
               "${n_known} known (known_up)")
