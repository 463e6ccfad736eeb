#include "apps/commands.h"

#include "core/error.h"

#include <iostream>

namespace candela::app {

int run_guarded(const std::function<int()>& body) {
    try {
        return body();
    } catch (const SceneError& e) {
        std::cerr << e.what() << "\n";
        return ExitBadInput;
    } catch (const InputError& e) {
        std::cerr << "error: " << e.what() << "\n";
        return ExitBadInput;
    } catch (const std::bad_alloc&) {
        std::cerr << "error: out of memory\n";
        return ExitBadInput;
    }
}

}  // namespace candela::app
