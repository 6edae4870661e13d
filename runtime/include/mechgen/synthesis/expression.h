/**
 * \file synthesis/expression.h
 * The function y = f(x) of a function-generation task (issue 28), as written in the task file
 * (`function: {expression: "log10(x)", ...}`): numbers, x, pi, e, + - * / ^ (right
 * associative; unary minus binds looser than ^: -x^2 = -(x^2)), parentheses and the functions
 * sin cos tan asin acos atan exp log (natural) log10 sqrt abs sinh cosh tanh. Parsed once into
 * a small postfix program (no allocation when evaluated). A bad expression: the column (1-based,
 * within the expression's text) and what is wrong. The parser is recursive: parentheses,
 * function calls, signs and powers nest at most kMaxNesting levels (the model reader's bound,
 * generator/model/reader.h kMaxExpressionNesting), so that no text can overflow the stack.
 */
#pragma once

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace mechgen::synthesis {

class Expression {
 public:
  /// The deepest nesting of parentheses, function calls, signs and powers.
  static constexpr int kMaxNesting = 64;

  /// Parses `text`; false, *column (1-based in text) and *error on a bad expression.
  bool Parse(const std::string& text, int* column, std::string* error) {
    text_ = text;
    pos_ = 0;
    code_.clear();
    error_.clear();
    depth_ = 0;
    if (!Sum() || (Skip(), pos_ != text_.size() && Fail("unexpected '" + std::string(1, text_[pos_]) + "'"))) {
      *column = static_cast<int>(error_pos_) + 1;
      *error = error_;
      code_.clear();
      return false;
    }
    return true;
  }

  /// f(x); NaN outside the functions' domains.
  double operator()(double x) const {
    double stack[64];
    int top = 0;
    for (const Op& op : code_) {
      switch (op.kind) {
        case kNum: stack[top++] = op.value; break;
        case kX: stack[top++] = x; break;
        case kNeg: stack[top - 1] = -stack[top - 1]; break;
        case kAdd: --top, stack[top - 1] += stack[top]; break;
        case kSub: --top, stack[top - 1] -= stack[top]; break;
        case kMul: --top, stack[top - 1] *= stack[top]; break;
        case kDiv: --top, stack[top - 1] /= stack[top]; break;
        case kPow: --top, stack[top - 1] = std::pow(stack[top - 1], stack[top]); break;
        case kCall: stack[top - 1] = Call(op.function, stack[top - 1]); break;
      }
    }
    return top == 1 ? stack[0] : std::nan("");
  }

  bool empty() const { return code_.empty(); }

 private:
  enum Kind { kNum, kX, kNeg, kAdd, kSub, kMul, kDiv, kPow, kCall };
  struct Op {
    Kind kind;
    double value = 0;
    int function = 0;
  };
  static const char* const* Functions() {
    static const char* const names[] = {"sin", "cos", "tan", "asin", "acos", "atan", "exp", "log", "log10",
                                        "sqrt", "abs", "sinh", "cosh", "tanh", nullptr};
    return names;
  }
  static double Call(int f, double v) {
    switch (f) {
      case 0: return std::sin(v);
      case 1: return std::cos(v);
      case 2: return std::tan(v);
      case 3: return std::asin(v);
      case 4: return std::acos(v);
      case 5: return std::atan(v);
      case 6: return std::exp(v);
      case 7: return std::log(v);
      case 8: return std::log10(v);
      case 9: return std::sqrt(v);
      case 10: return std::abs(v);
      case 11: return std::sinh(v);
      case 12: return std::cosh(v);
      default: return std::tanh(v);
    }
  }

  bool Fail(const std::string& what) {
    if (error_.empty()) error_ = what, error_pos_ = pos_;
    return false;
  }
  void Skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool Depth() { return code_.size() < 60 || Fail("the expression is too long (at most 60 operations)"); }
  // One level deeper (a '(', a function's argument, a sign, an exponent): false past kMaxNesting.
  bool Enter() {
    return ++depth_ <= kMaxNesting ||
           Fail("parentheses, function calls, signs or powers nested deeper than " + std::to_string(kMaxNesting) +
                " levels");
  }
  // sum := product (('+'|'-') product)*
  bool Sum() {
    if (!Product()) return false;
    for (;;) {
      Skip();
      if (pos_ >= text_.size() || (text_[pos_] != '+' && text_[pos_] != '-')) return true;
      const Kind k = text_[pos_++] == '+' ? kAdd : kSub;
      if (!Product()) return false;
      code_.push_back({k});
    }
  }
  // product := unary (('*'|'/') unary)*
  bool Product() {
    if (!Unary()) return false;
    for (;;) {
      Skip();
      if (pos_ >= text_.size() || (text_[pos_] != '*' && text_[pos_] != '/')) return true;
      const Kind k = text_[pos_++] == '*' ? kMul : kDiv;
      if (!Unary()) return false;
      code_.push_back({k});
    }
  }
  // unary := ('-'|'+') unary | power
  bool Unary() {
    Skip();
    if (pos_ < text_.size() && (text_[pos_] == '-' || text_[pos_] == '+')) {
      const bool neg = text_[pos_++] == '-';
      if (!Enter() || !Unary()) return false;
      --depth_;
      if (neg) code_.push_back({kNeg});
      return Depth();
    }
    return Power();
  }
  // power := atom ('^' unary)?
  bool Power() {
    if (!Atom()) return false;
    Skip();
    if (pos_ < text_.size() && text_[pos_] == '^') {
      ++pos_;
      if (!Enter() || !Unary()) return false;
      --depth_;
      code_.push_back({kPow});
    }
    return Depth();
  }
  bool Atom() {
    Skip();
    if (pos_ >= text_.size()) return Fail("expected a number, x, a function or '(' at the end");
    const char c = text_[pos_];
    if (c == '(') {
      if (!Enter()) return false;
      ++pos_;
      if (!Sum()) return false;
      Skip();
      if (pos_ >= text_.size() || text_[pos_] != ')') return Fail("expected ')'");
      ++pos_;
      --depth_;
      return true;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) return Fail("bad number");
      pos_ += static_cast<size_t>(end - begin);
      code_.push_back({kNum, v});
      return Depth();
    }
    if (std::isalpha(static_cast<unsigned char>(c))) {
      const size_t start = pos_;
      while (pos_ < text_.size() && std::isalnum(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      const std::string name = text_.substr(start, pos_ - start);
      if (name == "x") return code_.push_back({kX}), Depth();
      if (name == "pi") return code_.push_back({kNum, M_PI}), Depth();
      if (name == "e") return code_.push_back({kNum, M_E}), Depth();
      for (int f = 0; Functions()[f] != nullptr; ++f) {
        if (name != Functions()[f]) continue;
        Skip();
        if (pos_ >= text_.size() || text_[pos_] != '(') return Fail("expected '(' after " + name);
        if (!Enter()) return false;
        ++pos_;
        if (!Sum()) return false;
        Skip();
        if (pos_ >= text_.size() || text_[pos_] != ')') return Fail("expected ')'");
        ++pos_;
        --depth_;
        code_.push_back({kCall, 0, f});
        return Depth();
      }
      pos_ = start;
      return Fail("unknown name '" + name + "' (the variable is x; functions: sin cos tan asin acos atan exp log log10 "
                  "sqrt abs sinh cosh tanh; constants pi, e)");
    }
    return Fail("unexpected '" + std::string(1, c) + "'");
  }

  std::string text_, error_;
  size_t pos_ = 0, error_pos_ = 0;
  int depth_ = 0;
  std::vector<Op> code_;
};

}  // namespace mechgen::synthesis
