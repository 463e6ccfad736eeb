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
    } catch (const InternalError& e) {
        std::cerr << "internal error (a bug in Candela; please report it with the command that caused it): " << e.what() << "\n";
        return ExitInternalError;
    }
}

}  // namespace candela::app
