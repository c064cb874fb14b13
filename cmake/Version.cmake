# The version is project(VERSION) in CMakeLists.txt, nowhere else. The git commit is read at
# configure time (with "-dirty" when tracked files differ from it; "unknown" outside git) into
# lathectl_version.hpp, which only apps/lathectl/main.cpp includes. CMake re-runs when HEAD or its
# branch moves (a commit, a checkout), not on every build; edits after configuring are not seen
# until then.
set(LATHECTL_GIT_COMMIT unknown)
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --show-toplevel
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE _top RESULT_VARIABLE _rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  # Only this project's own repository: not a parent repository the sources were unpacked into.
  if(_rc EQUAL 0 AND _top)
    file(REAL_PATH "${_top}" _top)
    file(REAL_PATH "${PROJECT_SOURCE_DIR}" _src)
  endif()
  if(_rc EQUAL 0 AND _top STREQUAL _src)
    execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short HEAD
                    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    OUTPUT_VARIABLE _commit RESULT_VARIABLE _rc
                    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(_rc EQUAL 0 AND _commit)
      set(LATHECTL_GIT_COMMIT ${_commit})
      execute_process(COMMAND ${GIT_EXECUTABLE} status --porcelain --untracked-files=no
                      WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                      OUTPUT_VARIABLE _status RESULT_VARIABLE _rc ERROR_QUIET)
      if(NOT _rc EQUAL 0 OR NOT _status STREQUAL "")
        string(APPEND LATHECTL_GIT_COMMIT -dirty)
      endif()
      # Re-configure when HEAD or the branch it names moves.
      execute_process(COMMAND ${GIT_EXECUTABLE} symbolic-ref -q HEAD
                      WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                      OUTPUT_VARIABLE _branch OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      foreach(_ref HEAD ${_branch} packed-refs)
        execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --path-format=absolute --git-path ${_ref}
                        WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                        OUTPUT_VARIABLE _path OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
        if(_path AND EXISTS "${_path}")
          set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${_path}")
        endif()
      endforeach()
    endif()
  endif()
endif()
message(STATUS "lathectl ${PROJECT_VERSION} (commit ${LATHECTL_GIT_COMMIT})")
set(LATHECTL_GENERATED_DIR ${PROJECT_BINARY_DIR}/generated)
configure_file(${CMAKE_CURRENT_LIST_DIR}/lathectl_version.hpp.in
               ${LATHECTL_GENERATED_DIR}/lathectl_version.hpp @ONLY)
