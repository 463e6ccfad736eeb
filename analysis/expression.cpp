#include "analysis/expression.h"

#include "core/error.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace candela {

namespace {

// Recursive descent over the grammar
//   sum     = product { ("+" | "-") product }
//   product = unary { ("*" | "/") unary }
//   unary   = "-" unary | power
//   power   = atom [ "^" unary ]
//   atom    = number | "pi" | name "(" sum ")" | "(" sum ")"
class Parser {
public:
    explicit Parser(const std::string& text) : s_(text) {}

    double parse() {
        double v = sum();
        skip();
        if (i_ != s_.size()) fail("unexpected \"" + s_.substr(i_) + "\"");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError("expression \"" + s_ + "\" at position " + std::to_string(i_ + 1) + ": " + what);
    }
    void skip() {
        while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
    }
    bool accept(char c) {
        skip();
        if (i_ < s_.size() && s_[i_] == c) {
            ++i_;
            return true;
        }
        return false;
    }
    double sum() {
        double v = product();
        for (;;) {
            if (accept('+'))
                v += product();
            else if (accept('-'))
                v -= product();
            else
                return v;
        }
    }
    double product() {
        double v = unary();
        for (;;) {
            if (accept('*'))
                v *= unary();
            else if (accept('/'))
                v /= unary();
            else
                return v;
        }
    }
    double unary() {
        Nesting nesting(*this);
        if (accept('-')) return -unary();
        if (accept('+')) return unary();
        return power();
    }
    double power() {
        double base = atom();
        if (accept('^')) return std::pow(base, unary());
        return base;
    }
    double atom() {
        Nesting nesting(*this);
        skip();
        if (accept('(')) {
            double v = sum();
            if (!accept(')')) fail("missing \")\"");
            return v;
        }
        if (i_ < s_.size() && std::isalpha(static_cast<unsigned char>(s_[i_]))) {
            size_t start = i_;
            while (i_ < s_.size() && std::isalnum(static_cast<unsigned char>(s_[i_]))) ++i_;
            std::string name = s_.substr(start, i_ - start);
            if (name == "pi") return 3.14159265358979323846;
            if (!accept('(')) fail("unknown name \"" + name + "\"");
            double arg = sum();
            if (!accept(')')) fail("missing \")\"");
            if (name == "sqrt") return std::sqrt(arg);
            if (name == "exp") return std::exp(arg);
            if (name == "log") return std::log(arg);
            if (name == "sin") return std::sin(arg);
            if (name == "cos") return std::cos(arg);
            fail("unknown function \"" + name + "\"");
        }
        const char* begin = s_.c_str() + i_;
        char* end = nullptr;
        double v = std::strtod(begin, &end);
        if (end == begin) fail("expected a number");
        i_ += size_t(end - begin);
        return v;
    }

    // Each unary sign, "^", "(" and function call recurses: bounding the depth keeps a long run
    // of them (100000 "(") from overflowing the stack.
    static constexpr int MaxNesting = 1000;  // signs, "^" and "(" count one or two each
    struct Nesting {
        explicit Nesting(Parser& p) : parser(p) {
            if (++parser.depth_ > MaxNesting)
                parser.fail("nested too deeply (more than " + std::to_string(MaxNesting) + " levels of signs, powers and parentheses)");
        }
        ~Nesting() { --parser.depth_; }
        Parser& parser;
    };

    const std::string& s_;
    size_t i_ = 0;
    int depth_ = 0;
};

}  // namespace

double evaluate_expression(const std::string& text) {
    double v = Parser(text).parse();
    if (!std::isfinite(v)) throw InputError("expression \"" + text + "\" is not a finite number");
    return v;
}

}  // namespace candela
