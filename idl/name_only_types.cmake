# Post-processes the fastddsgen PubSubTypes output: the types that hold a sequence of structs (CausalFactorBatch:
# a sequence of OutcomeFactors; CausalFactorSet: a sequence of CausalFactorBatch) announce no TypeInformation and
# no TypeObject in discovery, set in their type support's constructor, so every program linked with these types
# (the services, the causal-twin-dev library an integrator builds against) sends them by name only.
# Why: Debian's Fast DDS 2.9.1 discovery server (fast-discovery-server) builds a dynamic type from every TypeObject
# an endpoint announces, and for a sequence-of-structs member TypeObjectFactory::get_sequence_identifier
# dereferences a null identifier (SIGSEGV): one reader or writer of such a type stopped discovery for the whole
# plant. Matching falls back to the type name when a side announces no type (EDP::checkTypeValidation), so
# readers and writers of these types still meet each other, with or without the flags.
# tests/dds/test_type_announcement.cpp checks that this list is every such type of the IDL.
#   cmake -DFILE=<generated PubSubTypes.cxx> -P name_only_types.cmake
set(NAME_ONLY_TYPES causal_twin::CausalFactorBatch causal_twin::CausalFactorSet)
file(READ "${FILE}" text)
foreach(type ${NAME_ONLY_TYPES})
  set(anchor "        setName(\"${type}\");\n")
  string(FIND "${text}" "${anchor}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "name_only_types.cmake: no setName(\"${type}\") found in ${FILE} (fastddsgen changed?)")
  endif()
  string(REPLACE "${anchor}"
         "${anchor}        auto_fill_type_object(false);  // name only: idl/name_only_types.cmake\n        auto_fill_type_information(false);\n"
         text "${text}")
endforeach()
file(WRITE "${FILE}" "${text}")
