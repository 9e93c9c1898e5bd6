# spinmotor_module(NAME <name> DEPS <public targets...> [PRIVATE_DEPS <targets...>])
# One library per module folder: headers in <name>/include/spinmotor/..., sources in <name>/src/*.cpp.
# Sources are globbed so that each file can be about one thing without touching this file.
function(spinmotor_module)
  cmake_parse_arguments(M "" "NAME" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB_RECURSE _src CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp")
  set(_tgt spinmotor_${M_NAME})
  if(_src)
    add_library(${_tgt} ${_src})
    target_include_directories(${_tgt} PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${_tgt} PUBLIC ${M_DEPS} PRIVATE ${M_PRIVATE_DEPS} $<BUILD_INTERFACE:spinmotor_flags>)
    target_compile_features(${_tgt} PUBLIC cxx_std_20)
    set_target_properties(${_tgt} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  else()
    add_library(${_tgt} INTERFACE)
    target_include_directories(${_tgt} INTERFACE
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(${_tgt} INTERFACE ${M_DEPS})
    target_compile_features(${_tgt} INTERFACE cxx_std_20)
  endif()
  set_target_properties(${_tgt} PROPERTIES EXPORT_NAME ${M_NAME})
  add_library(spinmotor::${M_NAME} ALIAS ${_tgt})
  install(TARGETS ${_tgt} EXPORT spinmotorTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()
