# firelook_add_package(): bake a VDB sequence into a .firelook package as a build step.
# Included by FireLookConfig.cmake, so find_package(FireLook) provides it; it runs the installed
# FireLook::firelook executable (`firelook bake`, docs/cli.md).
#
#   firelook_add_package(<name>
#     SEQUENCE <folder | pattern such as fire_####.vdb | one .vdb file>
#     OUTPUT <file.firelook>
#     [CONFIG <bake.json>] [SCENE <scene.gltf>] [FRAMES <A-B,...>]
#     [BAKE_ARGS <more firelook bake arguments>...]
#     [JOB_POOL <ninja pool>] [EXCLUDE_FROM_ALL])
#
# Quote a pattern: CMake reads an unquoted '#' as the start of a comment, so SEQUENCE fx/fire_####.vdb
# arrives as fx/fire_ (refused with a line that says so); write SEQUENCE "fx/fire_####.vdb".
#
# Relative SEQUENCE, CONFIG and SCENE paths are taken from the current source folder, a relative
# OUTPUT from the current binary folder. The package is rebaked when any of its inputs changes:
# every VDB file of the sequence (all of them, also with FRAMES: the default camera frames the
# whole sequence), the config, the scene and the firelook executable. The sequence's files are
# found when CMake configures, with CONFIGURE_DEPENDS, so a frame added or removed makes the next
# build reconfigure; the list of them is kept in <binary folder>/firelook/<name>.files, rewritten
# only when it changes and a dependency of the package, so that a removed frame rebakes it too
# (a missing input alone would not: the package is not older than any remaining file). Packages are independent build steps: Ninja or Make bakes them in parallel
# (a JOB_POOL caps how many at once; each bake already uses every core). The custom target
# <name> builds the package (part of `all` unless EXCLUDE_FROM_ALL); the bake writes it
# atomically, so an interrupted build leaves the previous package or none.
include_guard(GLOBAL)

# The files a sequence reads, as firelook finds them (formats/vdb/frame_files.h): for a folder its
# *.vdb files, for a pattern the files whose name is the pattern's prefix, digits and suffix.
function(_firelook_sequence_files out sequence)
  if(IS_DIRECTORY "${sequence}")
    file(GLOB files LIST_DIRECTORIES false CONFIGURE_DEPENDS "${sequence}/*.vdb")
  else()
    get_filename_component(folder "${sequence}" DIRECTORY)
    get_filename_component(name "${sequence}" NAME)
    if(name MATCHES "^([^#%]*)(#+|%[0-9]*d)(.*)$")
      set(prefix "${CMAKE_MATCH_1}")
      set(suffix "${CMAKE_MATCH_3}")
      file(GLOB candidates LIST_DIRECTORIES false CONFIGURE_DEPENDS "${folder}/${prefix}*${suffix}")
      set(files "")
      string(LENGTH "${prefix}" prefix_length)
      string(LENGTH "${suffix}" suffix_length)
      foreach(candidate IN LISTS candidates)
        get_filename_component(candidate_name "${candidate}" NAME)
        string(LENGTH "${candidate_name}" length)
        math(EXPR field_length "${length} - ${prefix_length} - ${suffix_length}")
        if(field_length GREATER 0)
          string(SUBSTRING "${candidate_name}" ${prefix_length} ${field_length} field)
          if(field MATCHES "^[0-9]+$")
            list(APPEND files "${candidate}")
          endif()
        endif()
      endforeach()
    elseif(EXISTS "${sequence}")
      set(files "${sequence}")
    else()
      set(files "")
    endif()
  endif()
  if(NOT files)
    # A pattern cut at its first '#' by CMake's comment rule leaves a prefix of the frame files.
    file(GLOB cut LIST_DIRECTORIES false "${sequence}[0-9]*")
    if(cut)
      message(FATAL_ERROR "firelook_add_package: SEQUENCE ${sequence} names no file, but files start with it: "
                          "an unquoted '#' starts a CMake comment, so quote the pattern, e.g. SEQUENCE \"fx/fire_####.vdb\"")
    endif()
    message(FATAL_ERROR "firelook_add_package: ${sequence}: no VDB file found (a folder of .vdb files, "
                        "a pattern such as \"fire_####.vdb\" (quoted), or one .vdb file)")
  endif()
  list(SORT files)
  set(${out} "${files}" PARENT_SCOPE)
endfunction()

function(firelook_add_package name)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "EXCLUDE_FROM_ALL" "SEQUENCE;OUTPUT;CONFIG;SCENE;FRAMES;JOB_POOL" "BAKE_ARGS")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "firelook_add_package(${name}): unknown arguments: ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  foreach(required SEQUENCE OUTPUT)
    if(NOT ARG_${required})
      message(FATAL_ERROR "firelook_add_package(${name}): ${required} is required")
    endif()
  endforeach()
  if(NOT TARGET FireLook::firelook)
    message(FATAL_ERROR "firelook_add_package(${name}): FireLook::firelook is not defined (find_package(FireLook) first)")
  endif()

  get_filename_component(sequence "${ARG_SEQUENCE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_filename_component(output "${ARG_OUTPUT}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  get_filename_component(output_dir "${output}" DIRECTORY)
  _firelook_sequence_files(inputs "${sequence}")
  # The set of frames as a file that changes only when the set does: a dependency of the package.
  set(file_list "${CMAKE_CURRENT_BINARY_DIR}/firelook/${name}.files")
  string(REPLACE ";" "\n" listed "${inputs}\n")
  set(previous "")
  if(EXISTS "${file_list}")
    file(READ "${file_list}" previous)
  endif()
  if(NOT previous STREQUAL listed)
    file(WRITE "${file_list}" "${listed}")
  endif()

  set(bake bake "${sequence}" -o "${output}")
  foreach(file_option CONFIG SCENE)
    if(ARG_${file_option})
      get_filename_component(path "${ARG_${file_option}}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
      if(NOT EXISTS "${path}")
        message(FATAL_ERROR "firelook_add_package(${name}): ${file_option} ${path} does not exist")
      endif()
      string(TOLOWER "${file_option}" option)
      list(APPEND bake "--${option}" "${path}")
      list(APPEND inputs "${path}")
    endif()
  endforeach()
  if(ARG_FRAMES)
    list(APPEND bake --frames "${ARG_FRAMES}")
  endif()
  list(APPEND bake ${ARG_BAKE_ARGS})

  set(pool "")
  if(ARG_JOB_POOL)
    set(pool JOB_POOL "${ARG_JOB_POOL}")
  endif()
  add_custom_command(OUTPUT "${output}"
    COMMAND "${CMAKE_COMMAND}" -E make_directory "${output_dir}"
    COMMAND FireLook::firelook ${bake}
    # The executable both as a target and as a file, so a new firelook rebakes.
    DEPENDS ${inputs} "${file_list}" FireLook::firelook "$<TARGET_FILE:FireLook::firelook>"
    COMMENT "Baking FireLook package ${name} (${output})"
    VERBATIM ${pool})
  set(all ALL)
  if(ARG_EXCLUDE_FROM_ALL)
    set(all "")
  endif()
  add_custom_target(${name} ${all} DEPENDS "${output}")
endfunction()
