# Warnings and sanitizers for FireLook's own targets. Third-party code is never
# compiled with -Werror: call firelook_target_defaults() on our targets only.

if(FIRELOOK_SANITIZE)
  # Applies to every target so that all code in one process is instrumented alike.
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
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
