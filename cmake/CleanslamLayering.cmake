# Dependencies point one way (docs/architecture.md):
#   tools        -> anything
#   firmware     -> slam_core, drivers, readers
#   paper_models -> slam_core
#   evaluation   -> readers
#   sim_hal      -> readers
#   slam_core, drivers, readers -> hal
# Each part lists the project parts it may link (hal always); configuring fails if a part links,
# directly or through other targets, a project part outside its list.
set(CLEANSLAM_LAYERED_PARTS cleanslam_hal cleanslam_slam_core cleanslam_drivers cleanslam_readers
    cleanslam_sim_hal cleanslam_evaluation cleanslam_paper_models cleanslam_firmware)
set(CLEANSLAM_ALLOWED_cleanslam_hal "")
set(CLEANSLAM_ALLOWED_cleanslam_slam_core cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_drivers cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_readers cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_sim_hal cleanslam_readers cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_evaluation cleanslam_readers cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_paper_models cleanslam_slam_core cleanslam_hal)
set(CLEANSLAM_ALLOWED_cleanslam_firmware cleanslam_slam_core cleanslam_drivers cleanslam_readers
    cleanslam_hal)

# The targets `target` links directly, aliases resolved and $<LINK_ONLY:...> unwrapped.
function(_cleanslam_links_of target out)
  set(result "")
  foreach(prop LINK_LIBRARIES INTERFACE_LINK_LIBRARIES)
    get_target_property(libs ${target} ${prop})
    if(libs)
      foreach(lib IN LISTS libs)
        if(lib MATCHES "^\\$<LINK_ONLY:(.+)>$")
          set(lib ${CMAKE_MATCH_1})
        endif()
        if(TARGET ${lib})
          get_target_property(aliased ${lib} ALIASED_TARGET)
          if(aliased)
            set(lib ${aliased})
          endif()
          list(APPEND result ${lib})
        endif()
      endforeach()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES result)
  set(${out} ${result} PARENT_SCOPE)
endfunction()

# Every target `target` links, directly or through other targets.
function(_cleanslam_closure_of target out)
  set(seen "")
  set(pending ${target})
  while(pending)
    list(POP_FRONT pending current)
    _cleanslam_links_of(${current} links)
    foreach(lib IN LISTS links)
      if(NOT lib IN_LIST seen)
        list(APPEND seen ${lib})
        list(APPEND pending ${lib})
      endif()
    endforeach()
  endwhile()
  set(${out} ${seen} PARENT_SCOPE)
endfunction()

function(cleanslam_enforce_layering)
  foreach(part IN LISTS CLEANSLAM_LAYERED_PARTS)
    if(NOT TARGET ${part})
      continue()
    endif()
    _cleanslam_closure_of(${part} links)
    foreach(lib IN LISTS links)
      if(lib IN_LIST CLEANSLAM_LAYERED_PARTS AND NOT lib IN_LIST CLEANSLAM_ALLOWED_${part})
        list(JOIN CLEANSLAM_ALLOWED_${part} ", " allowed)
        message(FATAL_ERROR "Layering violation: ${part} links ${lib}, which is not among the "
                            "parts it may use (${allowed}); see docs/architecture.md and "
                            "cmake/CleanslamLayering.cmake")
      endif()
    endforeach()
  endforeach()
endfunction()
