#include "scripting/basic/loader.hpp"

#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "scripting/basic/lexer.hpp"
#include "scripting/basic/parser.hpp"

namespace mcemu::basic {
namespace {

constexpr std::uint32_t k_none = std::numeric_limits<std::uint32_t>::max();

struct LabelDef {
  std::uint32_t pc = 0;
  std::uint32_t line = 0;
  int region = 0;
};

// A reference to a label, resolved after the scan.
struct LabelRef {
  std::uint32_t instr = 0;
  std::string name;
  std::uint32_t line = 0;
  int region = 0;
  bool is_goto = false;  // only GOTO is bound by the region rule
};

// An open IF block or FOR loop.
struct Block {
  bool is_if = true;
  std::uint32_t line = 0;
  int outer_region = 0;  // IF: the region holding the IF line
  std::uint32_t pending_false = k_none;
  std::vector<std::uint32_t> end_jumps{};
  bool seen_else = false;
  std::uint32_t for_instr = 0;  // FOR
  std::uint8_t var = 0;
};

std::string var_name(std::uint8_t v) { return std::string(1, static_cast<char>('a' + v)); }

class Loader {
 public:
  LoadResult run(std::string_view source) {
    if (source.size() > k_max_program_bytes) {
      return LoadError{0, "the program has " + std::to_string(source.size()) + " bytes; the limit is " +
                              std::to_string(k_max_program_bytes)};
    }
    const auto texts = split_lines(source);
    prog_.bytes = source.size();
    prog_.lines = static_cast<std::uint32_t>(texts.size());
    lines_.reserve(texts.size());
    for (auto t : texts) lines_.push_back(lex_line(t));

    for (std::size_t i = 0; i < lines_.size() && !error_; ++i) scan_line(i);
    if (error_) return *error_;
    if (!blocks_.empty()) {
      const Block& b = blocks_.back();
      return LoadError{b.line, b.is_if ? "IF without ENDIF" : "FOR without NEXT"};
    }
    emit(Instr{.op = Op::end, .line = prog_.lines});
    for (const auto& ref : refs_) {
      resolve(ref);
      if (error_) return *error_;
    }
    for (const auto& in : prog_.code) prog_.statements += in.cost;
    return std::move(prog_);
  }

 private:
  void fail(std::uint32_t line, std::string message) {
    if (!error_) error_ = LoadError{line, std::move(message)};
  }
  std::uint32_t here() const { return static_cast<std::uint32_t>(prog_.code.size()); }
  std::uint32_t emit(Instr in) {
    prog_.code.push_back(in);
    return here() - 1;
  }
  int new_region(int parent) {
    parents_.push_back(parent);
    return static_cast<int>(parents_.size()) - 1;
  }
  bool is_ancestor(int a, int r) const {  // a is a proper ancestor of r
    for (r = parents_[static_cast<std::size_t>(r)]; r >= 0; r = parents_[static_cast<std::size_t>(r)]) {
      if (r == a) return true;
    }
    return false;
  }

  // Whether the next line that is neither empty nor a comment begins with ELSEIF or ELSE.
  bool else_follows(std::size_t i) const {
    for (std::size_t j = i + 1; j < lines_.size(); ++j) {
      if (!lines_[j].error.empty()) return false;
      if (lines_[j].tokens.empty()) continue;
      const Token& t = lines_[j].tokens.front();
      return t.kind == Tok::word && (t.kw == Kw::elseif || t.kw == Kw::else_);
    }
    return false;
  }

  void scan_line(std::size_t i) {
    const auto line = static_cast<std::uint32_t>(i + 1);
    const LexedLine& l = lines_[i];
    if (!l.error.empty()) return fail(line, l.error);
    if (l.tokens.empty()) return;
    if (l.tokens.front().kind == Tok::label) {
      if (l.tokens.size() > 1) return fail(line, "a label line holds only the label (and a comment)");
      std::string name;
      for (char c : l.tokens.front().text) name.push_back(c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
      auto [it, fresh] = labels_.try_emplace(name, LabelDef{here(), line, region_});
      if (!fresh) {
        fail(line, "duplicate label '" + std::string(l.tokens.front().text) + "' (first at line " +
                       std::to_string(it->second.line) + ")");
      }
      return;
    }
    auto parsed = parse_statement(l.tokens, prog_.expr);
    if (!parsed.stmt) return fail(line, parsed.error);
    statement(*parsed.stmt, line, i);
  }

  // The innermost open IF, when it is the innermost block; reports why not otherwise.
  Block* open_if(std::uint32_t line, const char* what) {
    if (!blocks_.empty() && blocks_.back().is_if) return &blocks_.back();
    for (const auto& b : blocks_) {
      if (b.is_if) {
        fail(line, std::string(what) + " inside the FOR loop of line " + std::to_string(blocks_.back().line) +
                       " (its NEXT is missing)");
        return nullptr;
      }
    }
    fail(line, std::string(what) + " without IF");
    return nullptr;
  }

  void open_branch(Block& b, const Stmt& s, std::uint32_t line) {
    region_ = new_region(b.outer_region);
    b.pending_false = emit(Instr{.op = Op::jump_if_false, .cost = 1, .line = line, .a = s.a});
    if (s.inner) simple(*s.inner, line, 0);
  }

  void statement(const Stmt& s, std::uint32_t line, std::size_t i) {
    switch (s.kind) {
      case StmtKind::if_: {
        if (s.inner && !else_follows(i)) {  // the complete one-line form
          const auto jf = emit(Instr{.op = Op::jump_if_false, .cost = 1, .line = line, .a = s.a});
          simple(*s.inner, line, 0);
          prog_.code[jf].target = here();
          return;
        }
        if (++if_depth_ > k_max_if_nesting) {
          return fail(line, "IF blocks nested deeper than " + std::to_string(k_max_if_nesting) + " levels");
        }
        blocks_.push_back(Block{.is_if = true, .line = line, .outer_region = region_});
        open_branch(blocks_.back(), s, line);
        return;
      }
      case StmtKind::elseif:
      case StmtKind::else_: {
        const bool is_else = s.kind == StmtKind::else_;
        Block* b = open_if(line, is_else ? "ELSE" : "ELSEIF");
        if (!b) return;
        if (b->seen_else)
          return fail(line, std::string(is_else ? "a second ELSE" : "ELSEIF after ELSE") + " (IF at line " +
                                std::to_string(b->line) + ")");
        b->end_jumps.push_back(emit(Instr{.op = Op::jump, .line = line}));
        prog_.code[b->pending_false].target = here();
        if (!is_else) return open_branch(*b, s, line);
        b->pending_false = k_none;
        b->seen_else = true;
        region_ = new_region(b->outer_region);
        if (s.inner) simple(*s.inner, line, 1);
        return;
      }
      case StmtKind::endif: {
        Block* b = open_if(line, "ENDIF");
        if (!b) return;
        if (b->pending_false != k_none) prog_.code[b->pending_false].target = here();
        for (auto j : b->end_jumps) prog_.code[j].target = here();
        region_ = b->outer_region;
        blocks_.pop_back();
        --if_depth_;
        return;
      }
      case StmtKind::for_: {
        const auto slot = static_cast<std::uint32_t>(prog_.loops.size());
        prog_.loops.push_back(Loop{.var = s.var, .has_step = s.has_step, .from = s.a, .to = s.b, .step = s.c});
        const auto at = emit(Instr{.op = Op::for_init, .cost = 1, .var = s.var, .line = line, .slot = slot});
        blocks_.push_back(Block{.is_if = false, .line = line, .for_instr = at, .var = s.var});
        return;
      }
      case StmtKind::next: {
        if (blocks_.empty() || blocks_.back().is_if) {
          for (const auto& b : blocks_) {
            if (!b.is_if) {
              return fail(line, "NEXT inside the IF block of line " + std::to_string(blocks_.back().line) +
                                    " (its ENDIF is missing)");
            }
          }
          return fail(line, "NEXT without FOR");
        }
        const Block b = blocks_.back();
        if (s.has_var && s.var != b.var) {
          return fail(line, "NEXT " + var_name(s.var) + " does not match FOR " + var_name(b.var) + " (line " +
                                std::to_string(b.line) + ")");
        }
        const auto slot = prog_.code[b.for_instr].slot;
        emit(Instr{.op = Op::next, .cost = 1, .var = b.var, .line = line, .target = b.for_instr + 1, .slot = slot});
        prog_.code[b.for_instr].target = here();
        blocks_.pop_back();
        return;
      }
      default: simple(s, line, 1); return;
    }
  }

  void simple(const Stmt& s, std::uint32_t line, std::uint8_t cost) {
    Instr in{.cost = cost, .var = s.var, .sub = s.sub, .index = s.index, .line = line, .a = s.a};
    auto label_ref = [&](bool is_goto) { refs_.push_back(LabelRef{here(), s.label, line, region_, is_goto}); };
    switch (s.kind) {
      case StmtKind::assign: in.op = Op::assign; break;
      case StmtKind::setobj: in.op = Op::setobj; break;
      case StmtKind::goto_:
        in.op = Op::jump;
        label_ref(true);
        break;
      case StmtKind::gosub:
        in.op = Op::gosub;
        label_ref(false);
        break;
      case StmtKind::return_: in.op = Op::ret; break;
      case StmtKind::en_evt:
        in.op = Op::en_evt;
        label_ref(false);
        break;
      case StmtKind::di_evt: in.op = Op::di_evt; break;
      case StmtKind::def_evt_var: in.op = Op::def_evt_var; break;
      case StmtKind::ret_evt: in.op = Op::ret_evt; break;
      case StmtKind::def_tim_var: in.op = Op::def_tim_var; break;
      case StmtKind::start_tim: in.op = Op::start_tim; break;
      case StmtKind::def_cyc_var: in.op = Op::def_cyc_var; break;
      case StmtKind::start_cyc: in.op = Op::start_cyc; break;
      case StmtKind::stop_cyc: in.op = Op::stop_cyc; break;
      case StmtKind::save:
      case StmtKind::load:
        in.op = s.kind == StmtKind::save ? Op::save : Op::load;
        in.slot = static_cast<std::uint32_t>(prog_.lists.size());
        in.count = static_cast<std::uint32_t>(s.vars.size());
        prog_.lists.insert(prog_.lists.end(), s.vars.begin(), s.vars.end());
        break;
      default: return fail(line, "internal: a block statement where a simple one was expected");
    }
    emit(in);
  }

  void resolve(const LabelRef& ref) {
    const auto it = labels_.find(ref.name);
    if (it == labels_.end()) return fail(ref.line, "unknown label '" + ref.name + "'");
    const LabelDef& l = it->second;
    if (ref.is_goto && l.region != ref.region) {
      const std::string where = " (label at line " + std::to_string(l.line) + ")";
      if (is_ancestor(l.region, ref.region)) {
        return fail(ref.line, "GOTO " + ref.name + " leaves an IF block" + where);
      }
      if (is_ancestor(ref.region, l.region)) {
        return fail(ref.line, "GOTO " + ref.name + " jumps into an IF block" + where);
      }
      return fail(ref.line, "GOTO " + ref.name + " leaves its IF branch for another" + where);
    }
    prog_.code[ref.instr].target = l.pc;
  }

  Program prog_;
  std::vector<LexedLine> lines_;
  std::vector<Block> blocks_;
  std::vector<int> parents_{-1};  // region 0 = top level
  int region_ = 0;
  int if_depth_ = 0;
  std::unordered_map<std::string, LabelDef> labels_;
  std::vector<LabelRef> refs_;
  std::optional<LoadError> error_;
};

}  // namespace

LoadResult load(std::string_view source) { return Loader().run(source); }

}  // namespace mcemu::basic
