# cmake -DCORE=<absolute path of Filters/Core> -P CheckCoreLayering.cmake
# The core's dependencies run one way, down this table of layers: a folder includes (by
# quoted name) only its own headers and those of the folders it lists, CPU code and GPU code
# (its cuda/ subfolder: .h, .cuh, .cpp, .cu) alike; no core file includes VTK. The include
# paths of the CMake targets already refuse most breaches; this also catches relative paths
# ("../viewpoint/X.h"), includes that the include path of a CUDA build alone lets through,
# and a new folder that has no place in the table.
#
#   features            -> reduction, common   (the fused placement runs the reduction's
#                                               placement kernels on the features it computes)
#   reduction           -> common
#   transfer_function   -> common
#   viewpoint           -> common
#   common
#
# A quoted name is looked up as the compiler does: beside the including file, then in each
# folder the file may see ("cuda/X.h" is X.h of that folder's GPU code).
cmake_policy(SET CMP0057 NEW)
set(below_common "")
set(below_reduction common)
set(below_transfer_function common)
set(below_viewpoint common)
set(below_features reduction common)

file(GLOB entries LIST_DIRECTORIES true RELATIVE ${CORE} ${CORE}/*)
set(folders "")
set(bad "")
foreach(entry IN LISTS entries)
  if(IS_DIRECTORY ${CORE}/${entry})
    list(APPEND folders ${entry})
    if(NOT DEFINED below_${entry})
      list(APPEND bad "${entry}/: a folder with no place in the layer table of CheckCoreLayering.cmake")
    endif()
  endif()
endforeach()

foreach(folder IN LISTS folders)
  set(visible ${folder} ${below_${folder}})
  file(GLOB_RECURSE sources
    ${CORE}/${folder}/*.h ${CORE}/${folder}/*.cpp ${CORE}/${folder}/*.cuh ${CORE}/${folder}/*.cu)
  foreach(source IN LISTS sources)
    file(STRINGS ${source} includes REGEX "^[ \t]*#[ \t]*include")
    get_filename_component(dir ${source} DIRECTORY)
    file(RELATIVE_PATH file ${CORE} ${source})
    foreach(line IN LISTS includes)
      if(line MATCHES "[<\"](vtk[^>\"]*)")
        list(APPEND bad "${file}: ${CMAKE_MATCH_1} (the core never includes VTK)")
      elseif(line MATCHES "\"([^\"]+)\"")
        set(name "${CMAKE_MATCH_1}")
        if(name MATCHES "\\.\\./")
          list(APPEND bad "${file}: ${name} (a relative path up and out of its folder: include by name)")
          continue()
        endif()
        if(EXISTS ${dir}/${name})
          continue()
        endif()
        set(found FALSE)
        foreach(seen IN LISTS visible)
          if(EXISTS ${CORE}/${seen}/${name})
            set(found TRUE)
            break()
          endif()
        endforeach()
        if(found)
          continue()
        endif()
        set(owner "")
        foreach(other IN LISTS folders)
          if(EXISTS ${CORE}/${other}/${name})
            set(owner ${other})
            break()
          endif()
        endforeach()
        string(REPLACE ";" ", " shown_visible "${visible}")
        if(owner)
          list(APPEND bad "${file}: ${name} is ${owner}/${name}, above or beside ${folder}/ (it may include ${shown_visible})")
        else()
          list(APPEND bad "${file}: ${name} (no such header in ${shown_visible})")
        endif()
      endif()
    endforeach()
  endforeach()
endforeach()

list(LENGTH folders count)
if(bad)
  string(REPLACE ";" "\n  " shown "${bad}")
  message(FATAL_ERROR "includes against the core's layers:\n  ${shown}")
endif()
message(STATUS "${count} core folders: every include, CPU and GPU, within its folder or the folders below it")
