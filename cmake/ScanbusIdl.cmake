# Generates C++ types for every IDL file in a flat folder with fastddsgen (ROS 2 naming,
# case-sensitive) into the build tree, and builds them into one library. Users include them
# as "scanbus_msgs/<Type>.h" (and <Type>PubSubTypes.h), so a generated name never shadows
# another project's header.
# fastddsgen regenerates each included file too, so all files go to one folder and each
# generated source is compiled exactly once.
find_program(FASTDDSGEN fastddsgen REQUIRED)

function(scanbus_generate_idl target idl_dir)
  file(GLOB idl_files CONFIGURE_DEPENDS ${idl_dir}/*.idl)
  set(out_dir ${CMAKE_BINARY_DIR}/idl_gen/scanbus_msgs)
  set(sources "")
  foreach(idl ${idl_files})
    get_filename_component(name ${idl} NAME_WE)
    list(APPEND sources ${out_dir}/${name}.cxx ${out_dir}/${name}PubSubTypes.cxx)
  endforeach()
  add_custom_command(
    OUTPUT ${sources}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${out_dir}
    COMMAND ${FASTDDSGEN} -typeros2 -cs -replace -d ${out_dir} -I ${idl_dir} ${idl_files}
    DEPENDS ${idl_files}
    COMMENT "Generating DDS types from ${idl_dir}"
    VERBATIM)
  add_library(${target} STATIC ${sources})
  target_include_directories(${target} SYSTEM PUBLIC ${CMAKE_BINARY_DIR}/idl_gen)
  target_link_libraries(${target} PUBLIC fastrtps fastcdr)
  # Generated code is not ours to warn about.
  target_compile_options(${target} PRIVATE -w)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
