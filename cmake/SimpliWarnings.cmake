# Warnings for the project's own targets (not for the code VTK's wrappers generate).
function(simpli_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if (SIMPLI_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif ()
endfunction()
