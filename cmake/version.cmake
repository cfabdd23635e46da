# Writes src/core/version.hpp.in's header at every build (cmake -P, from the
# rpfem_version target), not only at configure time: a binary rebuilt after
# a commit names that commit. Project version + `git describe --dirty`
# (uncommitted changes in the tree at the build). configure_file leaves the
# header as it is when nothing changed, so nothing recompiles.
# In: SRC (the source tree), OUT (the header), PROJECT_VERSION.
execute_process(COMMAND git describe --always --dirty --abbrev=12
  WORKING_DIRECTORY ${SRC} OUTPUT_VARIABLE RPFEM_GIT
  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT RPFEM_GIT)
  set(RPFEM_GIT "unknown")
endif()
configure_file(${SRC}/src/core/version.hpp.in ${OUT} @ONLY)
