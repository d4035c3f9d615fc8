# Warnings and sanitizers for FireLook's own targets. Third-party code is never
# compiled with -Werror: call firelook_target_defaults() on our targets only.

if(FIRELOOK_SANITIZE)
  # Applies to every target so that all code in one process is instrumented alike.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# ThreadSanitizer excludes ASan. FIRELOOK_TSAN_RUNS: whether this compiler builds a program with it
# that also runs on this kernel (older TSan runtimes abort on some ASLR settings); tests built for
# TSan register only when it does.
if(FIRELOOK_SANITIZE_THREAD)
  if(FIRELOOK_SANITIZE)
    message(FATAL_ERROR "FIRELOOK_SANITIZE_THREAD and FIRELOOK_SANITIZE exclude each other")
  endif()
  include(CheckCXXSourceRuns)
  set(CMAKE_REQUIRED_FLAGS -fsanitize=thread)
  set(CMAKE_REQUIRED_LINK_OPTIONS -fsanitize=thread)
  check_cxx_source_runs("#include <thread>\nint main() { std::thread t([] {}); t.join(); }" FIRELOOK_TSAN_RUNS)
  unset(CMAKE_REQUIRED_FLAGS)
  unset(CMAKE_REQUIRED_LINK_OPTIONS)
  if(FIRELOOK_TSAN_RUNS)
    add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
    add_link_options(-fsanitize=thread)
    # target_clones dispatch through ifunc resolvers, which the loader runs before TSan has started;
    # instrumented, they crash the process. This flavour compiles the default clone only.
    add_compile_options("-Dtarget_clones(...)=unused")
  else()
    message(WARNING "ThreadSanitizer does not build or run here: no TSan tests are registered")
  endif()
endif()

function(firelook_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX,C>:-Wall -Wextra>
    $<$<AND:$<BOOL:${FIRELOOK_WERROR}>,$<COMPILE_LANGUAGE:CXX,C>>:-Werror>)
endfunction()

# firelook_add_library(<name> <sources...>): a static library firelook_<name>
# with the alias firelook::<name>, warnings on.
function(firelook_add_library name)
  add_library(firelook_${name} STATIC ${ARGN})
  add_library(firelook::${name} ALIAS firelook_${name})
  set_target_properties(firelook_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  firelook_target_defaults(firelook_${name})
endfunction()
