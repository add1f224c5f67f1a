# tavis_set_warnings(target): the project's warning set, applied to every first-party target.
# TAVIS_WERROR turns each warning into an error (CI's builds: .ci/build and .ci/sanitize), so a
# warning cannot land unnoticed; off by default, as a newer compiler's new warnings must not stop
# a user's build.
option(TAVIS_WERROR "Treat the project's compiler warnings as errors (CI)" OFF)
function(tavis_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
                                           -Wdouble-promotion -Wformat=2)
  if(TAVIS_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
