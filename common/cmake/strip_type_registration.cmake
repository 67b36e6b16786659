# Removes fastddsgen 2.3's TypeObject registration from the default constructors of the types it generates in
# DIR (run with cmake -DDIR=... -P after fastddsgen). Every constructed sample ran register<File>Types(): for
# each type TypeObjectFactory::add_type_object, a global lock and string-keyed map lookups. A frame block of
# 10 samples deserialised constructs 10 of them in every service, and each sensor_bias estimate one: perf on
# windfdi-sensor-bias at 160 turbines put about an eighth of its CPU there. The TypeObjects are registered
# once instead, where a content filter needs them (idl/register_type_objects.cpp with the participant, and
# TopicTraits<Estimate>::register_type_object for a service's estimate).
file(GLOB generated "${DIR}/*.cxx")
foreach(f IN LISTS generated)
  if(f MATCHES "(TypeObject|PubSubTypes)\\.cxx$")
    continue()
  endif()
  file(READ "${f}" text)
  string(REGEX REPLACE "\n[ \t]*// Just to register all known types\n[ \t]*register[A-Za-z0-9_]+Types\\(\\);" ""
         stripped "${text}")
  if(NOT stripped STREQUAL text)
    file(WRITE "${f}" "${stripped}")
  endif()
endforeach()
