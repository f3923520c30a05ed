# Post-processes the fastddsgen -typeobject output: its message constructors call register<idl>Types() every time
# (measured 5.5 us per VibrationFrame or CausalFactors object on this machine, against well under 0.1 us
# without), although the TypeObjectFactory needs the types only once, before the first type registration.
# causal::dds::Participant registers them once (std::call_once), so the per-object calls are removed here.
#   cmake -DFILE=<generated .cxx> -DSTEM=<idl stem> -P register_types_once.cmake
file(READ "${FILE}" text)
string(REPLACE "    register${STEM}Types();\n" "    // type objects: registered once by causal::dds::Participant (idl/register_types_once.cmake)\n"
       stripped "${text}")
if(stripped STREQUAL text)
  message(FATAL_ERROR "register_types_once.cmake: no register${STEM}Types() call found in ${FILE} (fastddsgen changed?)")
endif()
file(WRITE "${FILE}" "${stripped}")
