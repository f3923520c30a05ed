// Compiled (syntax only) by the ctest cases io_enum_names_*: with CASE 0 it must build; every other CASE is a name
// table that must not build (the checks of causal/io/enum_names.hpp), so those cases are WILL_FAIL.
#include "causal/io/enum_names.hpp"

namespace {

enum class Colour { red, green, blue };

#if CASE == 0
constexpr auto kNames =
    causal::io::enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}, {Colour::blue, "blue"}});
#elif CASE == 1  // an enumerator without a name
constexpr auto kNames = causal::io::enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}});
#elif CASE == 2  // an enumerator named twice (so another one not at all)
constexpr auto kNames =
    causal::io::enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}, {Colour::green, "verde"}});
#elif CASE == 3  // a name for a value that is no enumerator
constexpr auto kNames = causal::io::enum_names<Colour>(
    {{Colour::red, "red"}, {Colour::green, "green"}, {static_cast<Colour>(5), "five"}});
#endif

}  // namespace

const char* first_name() { return kNames.name(Colour::red, "?"); }
