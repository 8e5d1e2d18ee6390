#include "scripting/basic/parser.hpp"

#include <utility>

namespace mcemu::basic {
namespace {

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// The variable a word names (0 = a), or -1.
int variable_of(const Token& t) {
  if (t.kind != Tok::word || t.text.size() != 1) return -1;
  return lower(t.text[0]) - 'a';
}

class Parser {
 public:
  Parser(const std::vector<Token>& tokens, std::vector<XOp>& expr) : toks_(tokens), expr_(expr) {}

  ParsedLine line() {
    ParsedLine out;
    auto s = statement();
    if (s && !at_end()) {
      fail("unexpected " + describe(peek()) + " after the statement");
      s.reset();
    }
    if (!s) {
      out.error = error_.empty() ? "syntax error" : error_;
      return out;
    }
    out.stmt = std::move(s);
    return out;
  }

 private:
  const Token& peek() const { return pos_ < toks_.size() ? toks_[pos_] : end_; }
  bool at_end() const { return pos_ >= toks_.size(); }
  const Token& take() { return pos_ < toks_.size() ? toks_[pos_++] : end_; }
  bool accept(Tok k) {
    if (peek().kind != k) return false;
    ++pos_;
    return true;
  }
  bool accept_kw(Kw k) {
    if (peek().kind != Tok::word || peek().kw != k) return false;
    ++pos_;
    return true;
  }
  std::nullptr_t fail(std::string message) {
    if (error_.empty()) error_ = std::move(message);
    return nullptr;
  }

  bool variable(std::uint8_t& v, const char* what) {
    const int n = variable_of(peek());
    if (n < 0) {
      fail(std::string("expected a variable a … z ") + what + ", found " + describe(peek()));
      return false;
    }
    ++pos_;
    v = static_cast<std::uint8_t>(n);
    return true;
  }

  bool label(std::string& name, const char* what) {
    if (peek().kind != Tok::word) {
      fail(std::string("expected a label name ") + what + ", found " + describe(peek()));
      return false;
    }
    for (char c : take().text) name.push_back(lower(c));
    return true;
  }

  bool objref(Stmt& s, const char* keyword) {
    if (peek().kind != Tok::objref) {
      fail(std::string("expected an object reference $IIII.SS after ") + keyword + ", found " + describe(peek()));
      return false;
    }
    const Token& t = take();
    s.index = t.index;
    s.sub = t.sub;
    return true;
  }

  // ---- expressions (§9.4)

  bool expression(ExprRange& r) {
    r.begin = static_cast<std::uint32_t>(expr_.size());
    depth_ = 0;
    stack_ = 0;
    max_stack_ = 0;
    if (!or_expr()) return false;
    r.end = static_cast<std::uint32_t>(expr_.size());
    if (max_stack_ > k_max_expression_stack) {
      fail("expression too complex");
      return false;
    }
    return true;
  }

  void emit(X op, std::int32_t value = 0, std::uint16_t index = 0, std::uint8_t sub = 0) {
    expr_.push_back(XOp{op, sub, index, value});
    const bool push = op == X::constant || op == X::variable || op == X::getobj;
    const bool unary = op == X::neg || op == X::bnot || op == X::lnot;
    if (push) {
      ++stack_;
      if (stack_ > max_stack_) max_stack_ = stack_;
    } else if (!unary) {
      --stack_;
    }
  }

  bool deeper() {
    if (++depth_ > k_max_expression_nesting) {
      fail("expression nested too deeply");
      return false;
    }
    return true;
  }

  bool or_expr() {
    if (!and_expr()) return false;
    while (accept_kw(Kw::or_)) {
      if (!and_expr()) return false;
      emit(X::lor);
    }
    return true;
  }
  bool and_expr() {
    if (!not_expr()) return false;
    while (accept_kw(Kw::and_)) {
      if (!not_expr()) return false;
      emit(X::land);
    }
    return true;
  }
  bool not_expr() {
    if (accept_kw(Kw::not_)) {
      if (!deeper() || !not_expr()) return false;
      --depth_;
      emit(X::lnot);
      return true;
    }
    return compare_expr();
  }
  bool compare_expr() {
    if (!bor_expr()) return false;
    for (;;) {
      X op;
      switch (peek().kind) {
        case Tok::eq: op = X::eq; break;
        case Tok::ne: op = X::ne; break;
        case Tok::lt: op = X::lt; break;
        case Tok::gt: op = X::gt; break;
        case Tok::le: op = X::le; break;
        case Tok::ge: op = X::ge; break;
        default: return true;
      }
      ++pos_;
      if (!bor_expr()) return false;
      emit(op);
    }
  }
  bool bor_expr() {
    if (!band_expr()) return false;
    while (accept(Tok::pipe)) {
      if (!band_expr()) return false;
      emit(X::bor);
    }
    return true;
  }
  bool band_expr() {
    if (!add_expr()) return false;
    while (accept(Tok::amp)) {
      if (!add_expr()) return false;
      emit(X::band);
    }
    return true;
  }
  bool add_expr() {
    if (!mul_expr()) return false;
    for (;;) {
      X op;
      if (accept(Tok::plus)) {
        op = X::add;
      } else if (accept(Tok::minus)) {
        op = X::sub;
      } else {
        return true;
      }
      if (!mul_expr()) return false;
      emit(op);
    }
  }
  bool mul_expr() {
    if (!unary()) return false;
    for (;;) {
      X op;
      if (accept(Tok::star)) {
        op = X::mul;
      } else if (accept(Tok::slash)) {
        op = X::div;
      } else if (accept(Tok::percent)) {
        op = X::mod;
      } else {
        return true;
      }
      if (!unary()) return false;
      emit(op);
    }
  }
  bool unary() {
    X op;
    if (accept(Tok::minus)) {
      op = X::neg;
    } else if (accept(Tok::tilde)) {
      op = X::bnot;
    } else {
      return primary();
    }
    if (!deeper() || !unary()) return false;
    --depth_;
    emit(op);
    return true;
  }
  bool primary() {
    const Token& t = peek();
    switch (t.kind) {
      case Tok::number:
        ++pos_;
        emit(X::constant, static_cast<std::int32_t>(t.value));
        return true;
      case Tok::lparen:
        ++pos_;
        if (!deeper() || !or_expr()) return false;
        --depth_;
        if (!accept(Tok::rparen)) {
          fail("expected ')', found " + describe(peek()));
          return false;
        }
        return true;
      case Tok::word: {
        if (t.kw == Kw::getobj) {
          ++pos_;
          Stmt ref;
          if (!objref(ref, "GETOBJ")) return false;
          emit(X::getobj, 0, ref.index, ref.sub);
          return true;
        }
        const int v = variable_of(t);
        if (v >= 0) {
          ++pos_;
          emit(X::variable, v);
          return true;
        }
        if (t.kw == Kw::none) {
          fail("unknown name " + describe(t) + " (variables are the single letters a … z)");
          return false;
        }
        fail("expected a value, found " + describe(t));
        return false;
      }
      case Tok::objref: fail("an object reference needs GETOBJ in an expression: " + describe(t)); return false;
      default: fail("expected a value, found " + describe(t)); return false;
    }
  }

  // ---- statements (§9.3)

  std::unique_ptr<Stmt> statement() {
    const Token& t = peek();
    auto s = std::make_unique<Stmt>();
    if (t.kind != Tok::word) return fail("expected a statement, found " + describe(t));
    const int v = variable_of(t);
    if (v >= 0) {
      ++pos_;
      s->kind = StmtKind::assign;
      s->var = static_cast<std::uint8_t>(v);
      if (!accept(Tok::eq))
        return fail("expected '=' after the variable " + describe(t) + ", found " + describe(peek()));
      if (!expression(s->a)) return nullptr;
      return s;
    }
    ++pos_;
    switch (t.kw) {
      case Kw::setobj:
        s->kind = StmtKind::setobj;
        if (!objref(*s, "SETOBJ")) return nullptr;
        if (!accept(Tok::eq)) return fail("expected '=' after the object reference, found " + describe(peek()));
        if (!expression(s->a)) return nullptr;
        return s;
      case Kw::goto_:
      case Kw::gosub:
        s->kind = t.kw == Kw::goto_ ? StmtKind::goto_ : StmtKind::gosub;
        if (!label(s->label, t.kw == Kw::goto_ ? "after GOTO" : "after GOSUB")) return nullptr;
        return s;
      case Kw::return_: s->kind = StmtKind::return_; return s;
      case Kw::for_:
        s->kind = StmtKind::for_;
        if (!variable(s->var, "after FOR")) return nullptr;
        if (!accept(Tok::eq)) return fail("expected '=' after FOR " + describe(toks_[pos_ - 1]));
        if (!expression(s->a)) return nullptr;
        if (!accept_kw(Kw::to)) return fail("expected TO, found " + describe(peek()));
        if (!expression(s->b)) return nullptr;
        if (accept_kw(Kw::step)) {
          s->has_step = true;
          if (!expression(s->c)) return nullptr;
        }
        return s;
      case Kw::next:
        s->kind = StmtKind::next;
        if (!at_end()) {
          if (!variable(s->var, "after NEXT")) return nullptr;
          s->has_var = true;
        }
        return s;
      case Kw::if_:
      case Kw::elseif:
        s->kind = t.kw == Kw::if_ ? StmtKind::if_ : StmtKind::elseif;
        if (!expression(s->a)) return nullptr;
        if (!accept_kw(Kw::then)) return fail("expected THEN, found " + describe(peek()));
        return with_inner(std::move(s), t);
      case Kw::else_: s->kind = StmtKind::else_; return with_inner(std::move(s), t);
      case Kw::endif: s->kind = StmtKind::endif; return s;
      case Kw::en_evt:
        s->kind = StmtKind::en_evt;
        if (!expression(s->a)) return nullptr;
        if (!accept(Tok::comma))
          return fail("expected ',' and a label after the EN_EVT mask, found " + describe(peek()));
        if (!label(s->label, "after EN_EVT mask,")) return nullptr;
        return s;
      case Kw::di_evt: s->kind = StmtKind::di_evt; return s;
      case Kw::ret_evt: s->kind = StmtKind::ret_evt; return s;
      case Kw::def_evt_var:
      case Kw::def_tim_var:
      case Kw::def_cyc_var:
        s->kind = t.kw == Kw::def_evt_var   ? StmtKind::def_evt_var
                  : t.kw == Kw::def_tim_var ? StmtKind::def_tim_var
                                            : StmtKind::def_cyc_var;
        if (!variable(s->var, "after DEF_…_VAR")) return nullptr;
        return s;
      case Kw::start_tim:
        s->kind = StmtKind::start_tim;
        if (!expression(s->a)) return nullptr;
        return s;
      case Kw::start_cyc: s->kind = StmtKind::start_cyc; return s;
      case Kw::stop_cyc: s->kind = StmtKind::stop_cyc; return s;
      case Kw::save:
      case Kw::load:
        s->kind = t.kw == Kw::save ? StmtKind::save : StmtKind::load;
        do {
          std::uint8_t var = 0;
          if (!variable(var, t.kw == Kw::save ? "in the SAVE list" : "in the LOAD list")) return nullptr;
          s->vars.push_back(var);
        } while (accept(Tok::comma));
        return s;
      case Kw::none: return fail("unknown statement " + describe(t));
      default: return fail(describe(t) + " cannot start a statement");
    }
  }

  // The optional statement after IF … THEN, ELSEIF … THEN and ELSE.
  std::unique_ptr<Stmt> with_inner(std::unique_ptr<Stmt> s, const Token& head) {
    if (at_end()) return s;
    const Token& first = peek();
    auto inner = statement();
    if (!inner) return nullptr;
    if (!is_simple(inner->kind)) {
      return fail(describe(first) + " cannot follow " + (head.kw == Kw::else_ ? "ELSE" : "THEN") +
                  " on the same line (block statements need their own line)");
    }
    s->inner = std::move(inner);
    return s;
  }

  const std::vector<Token>& toks_;
  std::vector<XOp>& expr_;
  std::size_t pos_ = 0;
  Token end_{};
  std::string error_;
  int depth_ = 0;
  int stack_ = 0;
  int max_stack_ = 0;
};

}  // namespace

bool is_simple(StmtKind k) {
  switch (k) {
    case StmtKind::if_:
    case StmtKind::elseif:
    case StmtKind::else_:
    case StmtKind::endif:
    case StmtKind::for_:
    case StmtKind::next: return false;
    default: return true;
  }
}

ParsedLine parse_statement(const std::vector<Token>& tokens, std::vector<XOp>& expr) {
  return Parser(tokens, expr).line();
}

}  // namespace mcemu::basic
