// The syntax of one MC BASIC line (faulhaber.md §9.3, §9.4): a statement with its expressions.
// Expressions are appended to the program's expression vector in reverse Polish notation, with
// the precedence of §9.4 (high → low): primary; unary - ~; * / %; + -; &; |; comparisons; NOT;
// AND; OR. Binary operators are left-associative.
//
// Pure; used by the loader (loader.hpp), which builds the block structure from the statements.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "scripting/basic/lexer.hpp"
#include "scripting/basic/program.hpp"

namespace mcemu::basic {

enum class StmtKind : std::uint8_t {
  assign,
  setobj,
  goto_,
  gosub,
  return_,
  for_,
  next,
  if_,
  elseif,
  else_,
  endif,
  en_evt,
  di_evt,
  def_evt_var,
  ret_evt,
  def_tim_var,
  start_tim,
  def_cyc_var,
  start_cyc,
  stop_cyc,
  save,
  load,
};

struct Stmt {
  StmtKind kind = StmtKind::assign;
  std::uint8_t var = 0;  // assign, for_, next (has_var), def_*_var
  bool has_var = false;  // NEXT v
  std::uint16_t index = 0;
  std::uint8_t sub = 0;
  std::string label;  // goto_, gosub, en_evt: lower case
  ExprRange a;        // value, condition, mask, START_TIM value, FOR start
  ExprRange b;        // FOR end
  ExprRange c;        // FOR step
  bool has_step = false;
  std::vector<std::uint8_t> vars;  // SAVE, LOAD
  std::unique_ptr<Stmt> inner;     // the statement after IF … THEN, ELSEIF … THEN, ELSE
};

struct ParsedLine {
  std::unique_ptr<Stmt> stmt;  // null on error
  std::string error;
};

// Parses the tokens of one statement line (not a label line, not empty).
ParsedLine parse_statement(const std::vector<Token>& tokens, std::vector<XOp>& expr);

// The kinds that may follow THEN/ELSE on the same line (everything but the block statements).
bool is_simple(StmtKind k);

}  // namespace mcemu::basic
