# The build-info header both binaries include (armature/build_info.h): the
# project version and the git commit, read at configure time with nothing
# downloaded. Outside a git checkout (a tarball, even one unpacked inside some
# other repository) the commit is "unknown".
#
# Included from the top-level CMakeLists.txt it defines the INTERFACE target
# armature_build_info. Run as a script it writes one header, which is how the
# test checks the fallback:
#   cmake -DSOURCE_DIR=… -DVERSION=… -DHEADER=… -P cmake/BuildInfo.cmake

set(ARMATURE_BUILD_INFO_TEMPLATE ${CMAKE_CURRENT_LIST_DIR}/build_info.h.in)

# Sets `out` to the 12-digit commit of the checkout at `dir`, or "unknown";
# `git_files` to the files whose change means a new commit (HEAD and its ref).
# ARMATURE_GIT_COMMIT, when set, is taken instead: a build from sources that
# are not a checkout (the container build) can be told its commit.
function(armature_git_commit out git_files dir)
  set(commit unknown)
  set(files)
  find_package(Git QUIET)
  if(ARMATURE_GIT_COMMIT)
    if(ARMATURE_GIT_COMMIT MATCHES "^[0-9a-f]+$")
      set(commit ${ARMATURE_GIT_COMMIT})
    else()
      message(WARNING "ARMATURE_GIT_COMMIT '${ARMATURE_GIT_COMMIT}' is not a hexadecimal commit; using 'unknown'")
    endif()
  elseif(GIT_FOUND)
    execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --show-toplevel
      WORKING_DIRECTORY ${dir} OUTPUT_VARIABLE toplevel RESULT_VARIABLE toplevel_rc
      OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    file(REAL_PATH "${dir}" real_dir)
    if(toplevel_rc EQUAL 0)
      file(REAL_PATH "${toplevel}" toplevel)
    endif()
    # Only the checkout the sources are the root of, not a repository around them.
    if(toplevel_rc EQUAL 0 AND toplevel STREQUAL real_dir)
      execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD
        WORKING_DIRECTORY ${dir} OUTPUT_VARIABLE head RESULT_VARIABLE head_rc
        OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(head_rc EQUAL 0 AND head MATCHES "^[0-9a-f]+$")
        set(commit ${head})
      endif()
      execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --symbolic-full-name HEAD
        WORKING_DIRECTORY ${dir} OUTPUT_VARIABLE ref OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      foreach(path HEAD ${ref} packed-refs)
        execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --path-format=absolute --git-path ${path}
          WORKING_DIRECTORY ${dir} OUTPUT_VARIABLE file OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
        if(file AND EXISTS "${file}")
          list(APPEND files ${file})
        endif()
      endforeach()
    endif()
  endif()
  set(${out} ${commit} PARENT_SCOPE)
  set(${git_files} ${files} PARENT_SCOPE)
endfunction()

# Writes the header `header` for `version` and the checkout at `dir`
# (rewritten only when its contents change, so a reconfigure rebuilds nothing).
function(armature_write_build_info header version dir)
  armature_git_commit(ARMATURE_BUILD_COMMIT git_files ${dir})
  set(ARMATURE_BUILD_VERSION ${version})
  configure_file(${ARMATURE_BUILD_INFO_TEMPLATE} ${header} @ONLY)
  set(ARMATURE_BUILD_GIT_FILES ${git_files} PARENT_SCOPE)
  set(ARMATURE_BUILD_COMMIT ${ARMATURE_BUILD_COMMIT} PARENT_SCOPE)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
  armature_write_build_info(${HEADER} ${VERSION} ${SOURCE_DIR})
  return()
endif()

set(ARMATURE_GIT_COMMIT "" CACHE STRING "The git commit --version names when the sources are not a git checkout")
set(ARMATURE_BUILD_INFO_DIR ${CMAKE_BINARY_DIR}/generated)
armature_write_build_info(${ARMATURE_BUILD_INFO_DIR}/armature/build_info.h ${PROJECT_VERSION} ${CMAKE_SOURCE_DIR})
# A new commit (or checkout) reruns the configure step, so the commit stays true.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${ARMATURE_BUILD_GIT_FILES})
message(STATUS "armature ${PROJECT_VERSION}, commit ${ARMATURE_BUILD_COMMIT}")
add_library(armature_build_info INTERFACE)
target_include_directories(armature_build_info INTERFACE $<BUILD_INTERFACE:${ARMATURE_BUILD_INFO_DIR}>)
