// The model reader: the top level of a model file, the helpers every section reads with,
// and LoadModel. Each section has its own file in this folder (parameters.cc, links.cc,
// joints.cc, inputs.cc, outputs.cc, assembly.cc); the format is documented in
// models/README.md.
#include "model/reader.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

#include <yaml-cpp/eventhandler.h>

#include "joints/joint_kind.h"
#include "mechgen/io/format.h"
#include "model/expression_functions.h"

namespace mechgen {

SourceMark MarkOf(const YAML::Node& node) {
  const YAML::Mark m = node.Mark();
  if (m.is_null()) return {};
  return {m.line + 1, m.column + 1};
}

bool IsIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

namespace {

std::set<std::string> SplitWords(const char* text) {
  std::istringstream in(text);
  std::set<std::string> out;
  for (std::string w; in >> w;) out.insert(w);
  return out;
}

// C++20 keywords and alternative tokens.
const std::set<std::string>& Keywords() {
  static const std::set<std::string> words = SplitWords(
      "alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t "
      "char32_t class compl concept const consteval constexpr constinit const_cast continue co_await "
      "co_return co_yield decltype default delete do double dynamic_cast else enum explicit export "
      "extern false float for friend goto if inline int long mutable namespace new noexcept not "
      "not_eq nullptr operator or or_eq private protected public register reinterpret_cast requires "
      "return short signed sizeof static static_assert static_cast struct switch template this "
      "thread_local throw true try typedef typeid typename union unsigned using virtual void "
      "volatile wchar_t while xor xor_eq");
  return words;
}

// The macros (not beginning with an underscore) that the generated header's includes
// (<array>, <cmath>, <Eigen/Core>, <Eigen/LU>) define with GCC and glibc: `g++ -dM -E`
// (tests/generator/hostile_models_test.cc checks this list against the compiler's), plus
// NDEBUG and i386; every EIGEN_* name is taken as a macro too.
const std::set<std::string>& Macros() {
  static const std::set<std::string> words = SplitWords(R"(
    ADJ_ESTERROR ADJ_FREQUENCY ADJ_MAXERROR ADJ_MICRO ADJ_NANO ADJ_OFFSET ADJ_OFFSET_SINGLESHOT
    ADJ_OFFSET_SS_READ ADJ_SETOFFSET ADJ_STATUS ADJ_TAI ADJ_TICK ADJ_TIMECONST AIO_PRIO_DELTA_MAX
    ATOMIC_BOOL_LOCK_FREE ATOMIC_CHAR16_T_LOCK_FREE ATOMIC_CHAR32_T_LOCK_FREE ATOMIC_CHAR_LOCK_FREE
    ATOMIC_FLAG_INIT ATOMIC_INT_LOCK_FREE ATOMIC_LLONG_LOCK_FREE ATOMIC_LONG_LOCK_FREE
    ATOMIC_POINTER_LOCK_FREE ATOMIC_SHORT_LOCK_FREE ATOMIC_VAR_INIT ATOMIC_WCHAR_T_LOCK_FREE
    BC_BASE_MAX BC_DIM_MAX BC_SCALE_MAX BC_STRING_MAX BF16_PACKET_FUNCTION BIG_ENDIAN BOOL_MAX
    BOOL_WIDTH BUFSIZ BYTE_ORDER CHARCLASS_NAME_MAX CHAR_BIT CHAR_MAX CHAR_MIN CHAR_WIDTH
    CLOCKS_PER_SEC CLOCK_BOOTTIME CLOCK_BOOTTIME_ALARM CLOCK_MONOTONIC CLOCK_MONOTONIC_COARSE
    CLOCK_MONOTONIC_RAW CLOCK_PROCESS_CPUTIME_ID CLOCK_REALTIME CLOCK_REALTIME_ALARM
    CLOCK_REALTIME_COARSE CLOCK_TAI CLOCK_THREAD_CPUTIME_ID CLONE_CHILD_CLEARTID CLONE_CHILD_SETTID
    CLONE_DETACHED CLONE_FILES CLONE_FS CLONE_IO CLONE_NEWCGROUP CLONE_NEWIPC CLONE_NEWNET
    CLONE_NEWNS CLONE_NEWPID CLONE_NEWTIME CLONE_NEWUSER CLONE_NEWUTS CLONE_PARENT
    CLONE_PARENT_SETTID CLONE_PIDFD CLONE_PTRACE CLONE_SETTLS CLONE_SIGHAND CLONE_SYSVSEM
    CLONE_THREAD CLONE_UNTRACED CLONE_VFORK CLONE_VM COLL_WEIGHTS_MAX CPU_ALLOC CPU_ALLOC_SIZE
    CPU_AND CPU_AND_S CPU_CLR CPU_CLR_S CPU_COUNT CPU_COUNT_S CPU_EQUAL CPU_EQUAL_S CPU_FREE
    CPU_ISSET CPU_ISSET_S CPU_OR CPU_OR_S CPU_SET CPU_SETSIZE CPU_SET_S CPU_XOR CPU_XOR_S CPU_ZERO
    CPU_ZERO_S CSIGNAL DELAYTIMER_MAX E2BIG EACCES EADDRINUSE EADDRNOTAVAIL EADV EAFNOSUPPORT
    EAGAIN EALREADY EBADE EBADF EBADFD EBADMSG EBADR EBADRQC EBADSLT EBFONT EBUSY ECANCELED
    ECHILD ECHRNG ECOMM ECONNABORTED ECONNREFUSED ECONNRESET EDEADLK EDEADLOCK EDESTADDRREQ EDOM
    EDOTDOT EDQUOT EEXIST EFAULT EFBIG EHOSTDOWN EHOSTUNREACH EHWPOISON EIDRM EILSEQ EINPROGRESS
    EINTR EINVAL EIO EISCONN EISDIR EISNAM EKEYEXPIRED EKEYREJECTED EKEYREVOKED EL2HLT EL2NSYNC
    EL3HLT EL3RST ELIBACC ELIBBAD ELIBEXEC ELIBMAX ELIBSCN ELNRNG ELOOP EMEDIUMTYPE EMFILE EMLINK
    EMSGSIZE EMULTIHOP ENAMETOOLONG ENAVAIL ENETDOWN ENETRESET ENETUNREACH ENFILE ENOANO ENOBUFS
    ENOCSI ENODATA ENODEV ENOENT ENOEXEC ENOKEY ENOLCK ENOLINK ENOMEDIUM ENOMEM ENOMSG ENONET
    ENOPKG ENOPROTOOPT ENOSPC ENOSR ENOSTR ENOSYS ENOTBLK ENOTCONN ENOTDIR ENOTEMPTY ENOTNAM
    ENOTRECOVERABLE ENOTSOCK ENOTSUP ENOTTY ENOTUNIQ ENXIO EOF EOPNOTSUPP EOVERFLOW EOWNERDEAD
    EPERM EPFNOSUPPORT EPIPE EPROTO EPROTONOSUPPORT EPROTOTYPE ERANGE EREMCHG EREMOTE EREMOTEIO
    ERESTART ERFKILL EROFS ESHUTDOWN ESOCKTNOSUPPORT ESPIPE ESRCH ESRMNT ESTALE ESTRPIPE ETIME
    ETIMEDOUT ETOOMANYREFS ETXTBSY EUCLEAN EUNATCH EUSERS EWOULDBLOCK EXDEV EXFULL EXIT_FAILURE
    EXIT_SUCCESS EXPR_NEST_MAX F16_PACKET_FUNCTION FD_CLR FD_ISSET FD_SET FD_SETSIZE FD_ZERO
    FILENAME_MAX FOPEN_MAX FP_ILOGB0 FP_ILOGBNAN FP_INFINITE FP_INT_DOWNWARD FP_INT_TONEAREST
    FP_INT_TONEARESTFROMZERO FP_INT_TOWARDZERO FP_INT_UPWARD FP_LLOGB0 FP_LLOGBNAN FP_NAN
    FP_NORMAL FP_SUBNORMAL FP_ZERO HOST_NAME_MAX HUGE_VAL HUGE_VALF HUGE_VALL HUGE_VAL_F128
    HUGE_VAL_F32 HUGE_VAL_F32X HUGE_VAL_F64 HUGE_VAL_F64X INFINITY INT16_C INT16_MAX INT16_MIN
    INT16_WIDTH INT32_C INT32_MAX INT32_MIN INT32_WIDTH INT64_C INT64_MAX INT64_MIN INT64_WIDTH
    INT8_C INT8_MAX INT8_MIN INT8_WIDTH INTMAX_C INTMAX_MAX INTMAX_MIN INTMAX_WIDTH INTPTR_MAX
    INTPTR_MIN INTPTR_WIDTH INT_FAST16_MAX INT_FAST16_MIN INT_FAST16_WIDTH INT_FAST32_MAX
    INT_FAST32_MIN INT_FAST32_WIDTH INT_FAST64_MAX INT_FAST64_MIN INT_FAST64_WIDTH INT_FAST8_MAX
    INT_FAST8_MIN INT_FAST8_WIDTH INT_LEAST16_MAX INT_LEAST16_MIN INT_LEAST16_WIDTH INT_LEAST32_MAX
    INT_LEAST32_MIN INT_LEAST32_WIDTH INT_LEAST64_MAX INT_LEAST64_MIN INT_LEAST64_WIDTH
    INT_LEAST8_MAX INT_LEAST8_MIN INT_LEAST8_WIDTH INT_MAX INT_MIN INT_WIDTH IOV_MAX LC_ADDRESS
    LC_ADDRESS_MASK LC_ALL LC_ALL_MASK LC_COLLATE LC_COLLATE_MASK LC_CTYPE LC_CTYPE_MASK
    LC_GLOBAL_LOCALE LC_IDENTIFICATION LC_IDENTIFICATION_MASK LC_MEASUREMENT LC_MEASUREMENT_MASK
    LC_MESSAGES LC_MESSAGES_MASK LC_MONETARY LC_MONETARY_MASK LC_NAME LC_NAME_MASK LC_NUMERIC
    LC_NUMERIC_MASK LC_PAPER LC_PAPER_MASK LC_TELEPHONE LC_TELEPHONE_MASK LC_TIME LC_TIME_MASK
    LINE_MAX LITTLE_ENDIAN LLONG_MAX LLONG_MIN LLONG_WIDTH LOGIN_NAME_MAX LONG_BIT LONG_LONG_MAX
    LONG_LONG_MIN LONG_MAX LONG_MIN LONG_WIDTH L_ctermid L_cuserid L_tmpnam MATH_ERREXCEPT
    MATH_ERRNO MAXFLOAT MAX_CANON MAX_INPUT MB_CUR_MAX MB_LEN_MAX MOD_CLKA MOD_CLKB MOD_ESTERROR
    MOD_FREQUENCY MOD_MAXERROR MOD_MICRO MOD_NANO MOD_OFFSET MOD_STATUS MOD_TAI MOD_TIMECONST
    MQ_PRIO_MAX M_1_PI M_1_PIf M_1_PIf128 M_1_PIf32 M_1_PIf32x M_1_PIf64 M_1_PIf64x M_1_PIl M_2_PI
    M_2_PIf M_2_PIf128 M_2_PIf32 M_2_PIf32x M_2_PIf64 M_2_PIf64x M_2_PIl M_2_SQRTPI M_2_SQRTPIf
    M_2_SQRTPIf128 M_2_SQRTPIf32 M_2_SQRTPIf32x M_2_SQRTPIf64 M_2_SQRTPIf64x M_2_SQRTPIl M_E M_Ef
    M_Ef128 M_Ef32 M_Ef32x M_Ef64 M_Ef64x M_El M_LN10 M_LN10f M_LN10f128 M_LN10f32 M_LN10f32x
    M_LN10f64 M_LN10f64x M_LN10l M_LN2 M_LN2f M_LN2f128 M_LN2f32 M_LN2f32x M_LN2f64 M_LN2f64x
    M_LN2l M_LOG10E M_LOG10Ef M_LOG10Ef128 M_LOG10Ef32 M_LOG10Ef32x M_LOG10Ef64 M_LOG10Ef64x
    M_LOG10El M_LOG2E M_LOG2Ef M_LOG2Ef128 M_LOG2Ef32 M_LOG2Ef32x M_LOG2Ef64 M_LOG2Ef64x
    M_LOG2El M_PI M_PI_2 M_PI_2f M_PI_2f128 M_PI_2f32 M_PI_2f32x M_PI_2f64 M_PI_2f64x M_PI_2l
    M_PI_4 M_PI_4f M_PI_4f128 M_PI_4f32 M_PI_4f32x M_PI_4f64 M_PI_4f64x M_PI_4l M_PIf M_PIf128
    M_PIf32 M_PIf32x M_PIf64 M_PIf64x M_PIl M_SQRT1_2 M_SQRT1_2f M_SQRT1_2f128 M_SQRT1_2f32
    M_SQRT1_2f32x M_SQRT1_2f64 M_SQRT1_2f64x M_SQRT1_2l M_SQRT2 M_SQRT2f M_SQRT2f128 M_SQRT2f32
    M_SQRT2f32x M_SQRT2f64 M_SQRT2f64x M_SQRT2l NAME_MAX NAN NDEBUG NFDBITS NGROUPS_MAX NL_ARGMAX
    NL_LANGMAX NL_MSGMAX NL_NMAX NL_SETMAX NL_TEXTMAX NULL NZERO PATH_MAX PDP_ENDIAN PIPE_BUF
    PTHREAD_ADAPTIVE_MUTEX_INITIALIZER_NP PTHREAD_ATTR_NO_SIGMASK_NP PTHREAD_BARRIER_SERIAL_THREAD
    PTHREAD_CANCELED PTHREAD_CANCEL_ASYNCHRONOUS PTHREAD_CANCEL_DEFERRED PTHREAD_CANCEL_DISABLE
    PTHREAD_CANCEL_ENABLE PTHREAD_COND_INITIALIZER PTHREAD_CREATE_DETACHED PTHREAD_CREATE_JOINABLE
    PTHREAD_DESTRUCTOR_ITERATIONS PTHREAD_ERRORCHECK_MUTEX_INITIALIZER_NP PTHREAD_EXPLICIT_SCHED
    PTHREAD_INHERIT_SCHED PTHREAD_KEYS_MAX PTHREAD_MUTEX_INITIALIZER PTHREAD_ONCE_INIT
    PTHREAD_PROCESS_PRIVATE PTHREAD_PROCESS_SHARED PTHREAD_RECURSIVE_MUTEX_INITIALIZER_NP
    PTHREAD_RWLOCK_INITIALIZER PTHREAD_RWLOCK_WRITER_NONRECURSIVE_INITIALIZER_NP
    PTHREAD_SCOPE_PROCESS PTHREAD_SCOPE_SYSTEM PTHREAD_STACK_MIN PTRDIFF_MAX PTRDIFF_MIN
    PTRDIFF_WIDTH P_tmpdir RAND_MAX RENAME_EXCHANGE RENAME_NOREPLACE RENAME_WHITEOUT RE_DUP_MAX
    RTSIG_MAX SCHAR_MAX SCHAR_MIN SCHAR_WIDTH SCHED_BATCH SCHED_DEADLINE SCHED_FIFO SCHED_IDLE
    SCHED_ISO SCHED_OTHER SCHED_RESET_ON_FORK SCHED_RR SEEK_CUR SEEK_DATA SEEK_END SEEK_HOLE
    SEEK_SET SEM_VALUE_MAX SHRT_MAX SHRT_MIN SHRT_WIDTH SIG_ATOMIC_MAX SIG_ATOMIC_MIN
    SIG_ATOMIC_WIDTH SIZE_MAX SIZE_WIDTH SNAN SNANF SNANF128 SNANF32 SNANF32X SNANF64 SNANF64X
    SNANL SSIZE_MAX STA_CLK STA_CLOCKERR STA_DEL STA_FLL STA_FREQHOLD STA_INS STA_MODE STA_NANO
    STA_PLL STA_PPSERROR STA_PPSFREQ STA_PPSJITTER STA_PPSSIGNAL STA_PPSTIME STA_PPSWANDER
    STA_RONLY STA_UNSYNC TIMER_ABSTIME TIME_UTC TMP_MAX TTY_NAME_MAX UCHAR_MAX UCHAR_WIDTH
    UINT16_C UINT16_MAX UINT16_WIDTH UINT32_C UINT32_MAX UINT32_WIDTH UINT64_C UINT64_MAX
    UINT64_WIDTH UINT8_C UINT8_MAX UINT8_WIDTH UINTMAX_C UINTMAX_MAX UINTMAX_WIDTH UINTPTR_MAX
    UINTPTR_WIDTH UINT_FAST16_MAX UINT_FAST16_WIDTH UINT_FAST32_MAX UINT_FAST32_WIDTH
    UINT_FAST64_MAX UINT_FAST64_WIDTH UINT_FAST8_MAX UINT_FAST8_WIDTH UINT_LEAST16_MAX
    UINT_LEAST16_WIDTH UINT_LEAST32_MAX UINT_LEAST32_WIDTH UINT_LEAST64_MAX UINT_LEAST64_WIDTH
    UINT_LEAST8_MAX UINT_LEAST8_WIDTH UINT_MAX UINT_WIDTH ULLONG_MAX ULLONG_WIDTH ULONG_LONG_MAX
    ULONG_MAX ULONG_WIDTH USHRT_MAX USHRT_WIDTH WCHAR_MAX WCHAR_MIN WCHAR_WIDTH WCONTINUED
    WEOF WEXITED WEXITSTATUS WIFCONTINUED WIFEXITED WIFSIGNALED WIFSTOPPED WINT_MAX WINT_MIN
    WINT_WIDTH WNOHANG WNOWAIT WORD_BIT WSTOPPED WSTOPSIG WTERMSIG WUNTRACED XATTR_LIST_MAX
    XATTR_NAME_MAX XATTR_SIZE_MAX alloca assert assert_perror be16toh be32toh be64toh
    ei_declare_aligned_stack_constructed_variable ei_declare_local_nested_eval eigen_assert
    eigen_internal_assert eigen_plain_assert errno htobe16 htobe32 htobe64 htole16 htole32 htole64
    i386 issubnormal le16toh le32toh le64toh linux math_errhandling offsetof pthread_cleanup_pop
    pthread_cleanup_pop_restore_np pthread_cleanup_push pthread_cleanup_push_defer_np
    sched_priority stderr stdin stdout strdupa strndupa unix vec2d_duplane vec2d_swizzle1
    vec2d_swizzle2 vec4f_duplane vec4f_swizzle1 vec4f_swizzle2 vec4i_swizzle1 vec4i_swizzle2
)");
  return words;
}

// Names the generated code uses next to a parameter's member (Params<Scalar>, its Cast<T>
// and its local p, the function arguments q and phi) or around the model's namespace, and
// the names of the expression language (a parameter of that name could not be written).
const std::set<std::string>& GeneratedNames() {
  static const std::set<std::string> words =
      SplitWords("Scalar T p q phi Params Cast std Eigen mech mechgen");
  return words;
}
const std::set<std::string>& ExpressionNames() {
  static const std::set<std::string> words = SplitWords(
      "deg Pi pi u sin cos tan asin acos atan atan2 sqrt exp log abs step sign min max clamp mod pow I Euler "
      "Catalan");
  return words;
}
// The functions among them: what a table (called like one) must not be named.
const std::set<std::string>& ExpressionFunctionNames() {
  static const std::set<std::string> words = SplitWords(
      "sin cos tan asin acos atan atan2 sqrt exp log abs step sign min max clamp mod pow");
  return words;
}
// C and POSIX headers a model name must not shadow (<name>.h is written, and the model's
// include directory is put on the include path).
const std::set<std::string>& HeaderNames() {
  static const std::set<std::string> words = SplitWords(
      "assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal "
      "stdalign stdarg stdatomic stdbool stddef stdint stdio stdlib stdnoreturn string tgmath "
      "threads time uchar wchar wctype alloca dirent dlfcn fcntl features malloc memory poll "
      "pthread sched semaphore strings syslog termios unistd utime");
  return words;
}

const char* RoleName(NameRole role) {
  switch (role) {
    case NameRole::kModel: return "model";
    case NameRole::kParameter: return "parameter";
    case NameRole::kLink: return "link";
    case NameRole::kPoint: return "point";
    case NameRole::kJoint: return "joint";
    case NameRole::kTable: return "table";
  }
  return "";
}

}  // namespace

std::string NameProblem(const std::string& name, NameRole role) {
  if (name.empty()) return "is empty";
  for (unsigned char c : name)
    if (c >= 0x80) return "is not a C++ identifier: use ASCII letters, digits and _";
  if (!IsIdentifier(name))
    return "is not a C++ identifier (ASCII letters, digits and _, not beginning with a digit)";
  if (Keywords().count(name)) return "is a C++ keyword";
  if (name[0] == '_')
    return "begins with an underscore (reserved in C++, and it makes a double underscore in "
           "names such as theta_<link> or CamLaw_<joint>)";
  if (name.find("__") != std::string::npos) return "contains a double underscore (reserved in C++)";
  if (role != NameRole::kModel && role != NameRole::kParameter && role != NameRole::kTable) return "";
  if (Macros().count(name) || name.rfind("EIGEN_", 0) == 0)
    return "is a macro of the headers the generated code includes (<cmath>, <array>, Eigen)";
  if (GeneratedNames().count(name))
    return "is a name the generated code uses (Scalar, T, p, q, phi, Params, Cast, std, Eigen, mech, mechgen)";
  if (role == NameRole::kTable && ExpressionFunctionNames().count(name))
    return "is a function of the expression language: '" + name + "(x)' in an expression calls the function, "
           "never the table";
  if ((role == NameRole::kParameter || role == NameRole::kTable) && ExpressionNames().count(name))
    return "is a name of the expression language (deg, Pi, u, sin, cos, sqrt, ...)";
  if (role == NameRole::kModel) {
    if (name.back() == '_')
      return "ends with an underscore (the generated macro MECH_<NAME>_INSTANTIATING would contain a double underscore)";
    if (HeaderNames().count(name)) return "would write " + name + ".h, which shadows the C header <" + name + ".h>";
  }
  return "";
}

void CheckName(const Model& m, const std::string& name, NameRole role, SourceMark mark) {
  const std::string why = NameProblem(name, role);
  if (!why.empty())
    m.Fail(mark, std::string(RoleName(role)) + " name '" + name + "' " + why + "; rename it (see Names in models/README.md)");
}

std::string FreeTextProblem(const std::string& text, bool multiline) {
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n' && multiline) continue;
    if (c == '\n') return "has a line break (it is one line)";
    if ((c < 0x20 && c != '\t') || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "0x%02x", c);
      return std::string("has the control character ") + buf;
    }
    if (c < 0x80) continue;
    // UTF-8: a lead byte and its continuation bytes, no overlong forms or surrogates.
    const int n = c >= 0xf0 && c <= 0xf4 ? 3 : c >= 0xe0 ? 2 : c >= 0xc2 && c <= 0xdf ? 1 : -1;
    if (n < 0 || i + n >= text.size()) return "is not valid UTF-8";
    const unsigned char c1 = static_cast<unsigned char>(text[i + 1]);
    if ((c == 0xe0 && c1 < 0xa0) || (c == 0xed && c1 > 0x9f) || (c == 0xf0 && c1 < 0x90) || (c == 0xf4 && c1 > 0x8f))
      return "is not valid UTF-8";
    for (int k = 1; k <= n; ++k)
      if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return "is not valid UTF-8";
    i += n;
  }
  // A backslash (or the trigraph ??/) at the end of a line splices the next line onto a
  // // comment.
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.pop_back();
    if (!line.empty() && line.back() == '\\')
      return "ends a line with a backslash (it would continue the C++ comment onto the next line of code)";
    if (line.size() >= 3 && line.compare(line.size() - 3, 3, "?" "?/") == 0)
      return "ends a line with the trigraph ?" "?/ (a backslash in older C++)";
  }
  return "";
}

bool KeyTable::Accepts(const std::string& key) const {
  for (const Key& k : keys)
    if (key == k.name) return true;
  return false;
}

const KeyTable& ModelKeys() {
  static const KeyTable table{"model",
                              {{"name", "C++ identifier: the namespace mech::<name> (or --name)", true},
                               {"title", "one line, copied into the generated header", false},
                               {"description", "free text, copied into the generated header", false},
                               {"parameters", "named numbers: the generated Params struct", false},
                               {"links", "the links and their points; one is the ground", true},
                               {"joints", "the joints between the links", true},
                               {"inputs", "the generalized coordinates q, in order: driven joints, link angles, point coordinates", true},
                               {"gravity", "[gx, gy]: gravity in the fixed frame (statics, dynamics)", false},
                               {"loads", "forces at link points and torques on links", false},
                               {"springs", "linear springs between link points, torsional at revolute joints", false},
                               {"friction", "Coulomb and viscous friction per revolute or prismatic joint", false},
                               {"dampers", "viscous dampers between link points, torsional at revolute joints (dynamics)", false},
                               {"tables", "piecewise-linear functions of one argument, for loads (dynamics)", false},
                               {"outputs", "what the generated code computes", false},
                               {"design", "the design parameters the outputs are differentiated with respect to", false},
                               {"assembly", "coordinate values near the wanted assembly mode", false},
                               {"assembly_modes", "named assembly modes: {name: {coordinate: value, ...}, ...}", false}}};
  return table;
}

std::vector<const KeyTable*> AllKeyTables() {
  std::vector<const KeyTable*> out = {&ModelKeys(),  &ParameterKeys(), &LinkKeys(),      &JointKeys(),
                                      &InputKeys(),  &OutputKeys(),    &LawSegmentKeys(), &ContourKeys(),
                                      &LoadKeys(),   &SpringKeys(),     &FrictionKeys(),   &DamperKeys(),
                                      &TableKeys(),  &PointMassKeys(),   &DesignKeys()};
  for (const JointKind* k : JointKinds()) out.push_back(&k->Keys());
  return out;
}

double ValueAtDefaults(const Model& m, const GiNaC::ex& expr, SourceMark mark, const std::string& what) {
  GiNaC::ex e;
  try {
    e = expr.subs(m.Defaults()).evalf();
  } catch (const std::exception& err) {  // GiNaC: a division by zero; CLN: over- or underflow
    std::string why = err.what();
    m.Fail(mark, what + " cannot be evaluated at the parameters' defaults (" + why.substr(0, why.find('\n')) +
                     "); change the expression or the defaults");
  }
  if (!GiNaC::is_a<GiNaC::numeric>(e) || !GiNaC::ex_to<GiNaC::numeric>(e).is_real())
    m.Fail(mark, what + " must evaluate to a real number");
  const double v = GiNaC::ex_to<GiNaC::numeric>(e).to_double();
  if (!std::isfinite(v)) m.Fail(mark, what + " is not finite");
  return v;
}

void SectionReader::Fail(const YAML::Node& node, const std::string& message) const { m_.Fail(MarkOf(node), message); }

std::vector<std::pair<std::string, YAML::Node>> SectionReader::Entries(const YAML::Node& map, const std::string& what,
                                                                       const KeyTable* table) const {
  if (!map.IsMap()) Fail(map, what + " must be a mapping (key: value)");
  std::vector<std::pair<std::string, YAML::Node>> out;
  std::set<std::string> seen;
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (!it->first.IsScalar()) Fail(it->first, what + ": keys must be plain names");
    const std::string key = it->first.as<std::string>();
    if (!seen.insert(key).second) Fail(it->first, "duplicate name '" + key + "' in " + what + "; names must be unique");
    if (table && !table->Accepts(key)) {
      // In a { } mapping a comma ends the value: `{doc: crank AB, the input}` makes a key
      // 'the input' with no value out of the text's second half. Said at the text, with the fix.
      if (map.Style() == YAML::EmitterStyle::Flow && it->second.IsNull() && it != map.begin()) {
        auto before = map.begin();
        for (auto next = std::next(before); next != it; ++next) before = next;
        if (before->second.IsScalar() && before->first.IsScalar())
          Fail(before->second, "the " + before->first.as<std::string>() + ": text of " + what +
                                   " ends at a comma (in a { } mapping a comma ends a value, and '" + key +
                                   "' became a key); quote the whole text: " + before->first.as<std::string>() +
                                   ": \"" + before->second.as<std::string>() + ", " + key + "\"");
      }
      std::set<std::string> sorted;
      for (const Key& k : table->keys) sorted.insert(k.name);
      std::string list;
      for (const auto& a : sorted) list += (list.empty() ? "" : ", ") + a;
      Fail(it->first, "unknown key '" + key + "' in " + what + "; expected one of: " + list);
    }
    out.emplace_back(key, it->second);
    keymarks_[it->second.Mark().pos] = MarkOf(it->first);
    keynames_[it->second.Mark().pos] = key;
  }
  return out;
}

std::string SectionReader::Scalar(const YAML::Node& node, const std::string& what) const {
  // A key written without its value (`stiffness:`, `at: ~`) is YAML's null.
  if (node.IsNull()) {
    const auto key = keynames_.find(node.Mark().pos);
    Fail(node, what + (key == keynames_.end() ? std::string() : ": " + key->second) +
                   " has no value (the key is there, its value is empty); write the value after the colon");
  }
  if (!node.IsScalar()) Fail(node, what + " must be a single value; give one value, not a list or a mapping");
  return node.as<std::string>();
}

bool SectionReader::Bool(const YAML::Node& node, const std::string& what) const {
  const std::string v = Scalar(node, what);
  if (v != "true" && v != "false") Fail(node, what + " must be true or false");
  return v == "true";
}

// The functions of the expression language and their numbers of arguments: what GiNaC reads
// and the C++ printer (codegen/cxx_code.cc) emits.
const std::map<std::string, int>& ExpressionFunctions() {
  static const std::map<std::string, int> f = {
      {"sin", 1},  {"cos", 1},  {"tan", 1},  {"asin", 1}, {"acos", 1}, {"atan", 1},  {"atan2", 2},
      {"sqrt", 1}, {"exp", 1},  {"log", 1},  {"abs", 1},  {"step", 1}, {"sign", 1},  {"min", 2},
      {"max", 2},  {"mod", 2},  {"clamp", 3}};
  return f;
}

namespace {

const std::map<std::string, int>& Functions() { return ExpressionFunctions(); }

std::string FunctionList() {
  std::string list;
  for (const auto& [name, n] : Functions()) list += (list.empty() ? "" : " ") + name;
  return list;
}

struct ExpressionFailure {
  size_t offset;
  std::string message;
};

std::string CharText(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  if (u < 0x20 || u >= 0x7f) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "the byte 0x%02x", u);
    return buf;
  }
  return std::string("'") + c + "'";
}

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// The syntax of the expression language (models/README.md, "Expressions"), checked before
// GiNaC's recursive parser sees the text: nesting is bounded, names are known, and an error
// has its character.
//   expression := term (('+' | '-') term)*
//   term       := operand (('*' | '/') operand)*
//   operand    := ('+' | '-')* primary ['^' primary]   (signs only first in an expression)
//   primary    := number | name | function '(' expression (',' expression)* ')' | '(' expression ')'
class ExpressionSyntax {
 public:
  ExpressionSyntax(const std::string& text, const std::set<std::string>& names,
                   const std::set<std::string>* tables = nullptr,
                   const std::vector<std::pair<std::string, SourceMark>>* pending = nullptr)
      : t_(text), names_(names), tables_(tables), pending_(pending) {}

  void Check() {
    if (t_.size() > kMaxExpressionLength)
      Fail(0, "it is longer than " + std::to_string(kMaxExpressionLength) + " characters");
    Skip();
    if (i_ == t_.size()) Fail(0, "it is empty");
    Expression();
    Skip();
    if (i_ < t_.size()) {
      if (t_[i_] == ')') Fail(i_, "a ')' without its '('");
      Fail(i_, "unexpected " + CharText(t_[i_]) + " after a complete expression (an operator missing?)");
    }
  }

 private:
  [[noreturn]] void Fail(size_t at, const std::string& message) const { throw ExpressionFailure{at, message}; }
  void Skip() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t')) ++i_;
  }
  bool At(char c) {
    Skip();
    return i_ < t_.size() && t_[i_] == c;
  }
  // What the checker knows of a sub-expression: constant (no parameter, table or load
  // coordinate in it) and then its value in double (inf or NaN when out of double's range).
  struct Value {
    bool constant = false;
    double v = 0;
  };
  static Value Combine(const Value& a, const Value& b, double v) { return {a.constant && b.constant, v}; }
  // A sign right after a binary operator is refused: GiNaC's reader takes it for the sign of
  // everything that follows (it reads 3 * -1 + 4 as 3 * (-1 + 4) and 2^-1*4 as 2^(-4)).
  void NoSignAfter(char op) {
    if (At('+') || At('-'))
      Fail(i_, std::string("a sign right after '") + op + "': write a " + op + " (" + t_[i_] +
                   "b) in parentheses (GiNaC's reader would apply the sign to all that follows)");
  }
  Value Expression() {
    Value a = Term();
    while (At('+') || At('-')) {
      const char op = t_[i_];
      const bool minus = op == '-';
      ++i_;
      NoSignAfter(op);
      const Value b = Term();
      a = Combine(a, b, minus ? a.v - b.v : a.v + b.v);
    }
    return a;
  }
  Value Term() {
    Value a = Operand();
    while (At('*') || At('/')) {
      const char op = t_[i_];
      const bool divide = op == '/';
      ++i_;
      if (At('*') || At('/')) Fail(i_, "unexpected " + CharText(t_[i_]) + " (write a^b for a power)");
      NoSignAfter(op);
      const Value b = Operand();
      a = Combine(a, b, divide ? a.v / b.v : a.v * b.v);
    }
    return a;
  }
  Value Operand() {
    const bool negative = Signs();
    Value base = Primary();
    if (At('^')) {
      const size_t hat = i_;
      ++i_;
      NoSignAfter('^');
      Value exponent = Primary();
      if (At('^')) Fail(i_, "a second '^' in a row: write (a^b)^c or a^(b^c)");
      if (exponent.constant && !(std::abs(exponent.v) <= kMaxConstantExponent))
        Fail(hat, "a power whose exponent is a constant beyond " + G(kMaxConstantExponent) +
                      " in magnitude (its exact value cannot be computed in reasonable time)");
      if (exponent.constant && base.constant) {
        const double digits = std::abs(exponent.v) * std::max(1.0, std::abs(std::log10(std::abs(base.v))));
        if (!(digits <= kMaxExactDigits))
          Fail(hat, "a power of constants whose exact value would have about " + G(digits) + " digits (at most " +
                        G(kMaxExactDigits) + ")");
      }
      base = Combine(base, exponent, std::pow(base.v, exponent.v));
    }
    if (negative) base.v = -base.v;
    return base;
  }
  bool Signs() {
    bool negative = false;
    while (At('+') || At('-')) negative ^= t_[i_++] == '-';
    return negative;
  }
  void Open() {
    if (++depth_ > kMaxExpressionNesting)
      Fail(i_, "parentheses nested deeper than " + std::to_string(kMaxExpressionNesting) + " levels");
    ++i_;
  }
  void Close(size_t open) {
    if (!At(')')) {
      if (i_ == t_.size()) Fail(open, "this '(' is not closed");
      Fail(i_, "unexpected " + CharText(t_[i_]) + "; expected ')'");
    }
    ++i_;
    --depth_;
  }
  static bool IsNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
  static double Apply(const std::string& f, const std::vector<double>& x) {
    if (f == "sin") return std::sin(x[0]);
    if (f == "cos") return std::cos(x[0]);
    if (f == "tan") return std::tan(x[0]);
    if (f == "asin") return std::asin(x[0]);
    if (f == "acos") return std::acos(x[0]);
    if (f == "atan") return std::atan(x[0]);
    if (f == "atan2") return std::atan2(x[0], x[1]);
    if (f == "sqrt") return std::sqrt(x[0]);
    if (f == "exp") return std::exp(x[0]);
    if (f == "log") return std::log(x[0]);
    if (f == "abs") return std::abs(x[0]);
    if (f == "step") return StepValue(x[0]);
    if (f == "sign") return SignValue(x[0]);
    if (f == "min") return MinValue(x[0], x[1]);
    if (f == "max") return MaxValue(x[0], x[1]);
    if (f == "clamp") return MinValue(MaxValue(x[0], x[1]), x[2]);
    if (f == "mod") return x[1] > 0 ? ModValue(x[0], x[1]) : NAN;
    return NAN;
  }
  Value Primary() {
    Skip();
    if (i_ == t_.size()) Fail(i_, "it ends where a number, a name or '(' is expected");
    const char c = t_[i_];
    if (c == '(') {
      const size_t open = i_;
      Open();
      const Value v = Expression();
      Close(open);
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return {true, Number()};
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = i_;
      while (i_ < t_.size() && IsNameChar(t_[i_])) ++i_;
      const std::string name = t_.substr(start, i_ - start);
      const auto fn = Functions().find(name);
      const bool table = tables_ && tables_->count(name);
      if (At('(')) {
        if (fn == Functions().end() && !table) {
          std::string more;
          if (tables_) {
            for (const auto& t : *tables_) more += (more.empty() ? "" : " ") + t;
            more = more.empty() ? "; the model has no tables:" : "; the model's tables: " + more;
          }
          Fail(start, "'" + name + "' is not a function of the expression language (" + FunctionList() + ")" + more);
        }
        const int wanted = table ? 1 : fn->second;
        const size_t open = i_;
        Open();
        std::vector<double> x;
        bool constant = !table;
        const Value first = Expression();
        x.push_back(first.v);
        constant = constant && first.constant;
        while (At(',')) {
          ++i_;
          const Value more = Expression();
          x.push_back(more.v);
          constant = constant && more.constant;
        }
        Close(open);
        const int args = static_cast<int>(x.size());
        if (args != wanted)
          Fail(start, name + " takes " + std::to_string(wanted) + " argument" + (wanted > 1 ? "s" : "") + ", not " +
                          std::to_string(args));
        return {constant, constant ? Apply(name, x) : 0.0};
      }
      if (table) Fail(start, "the table " + name + " needs its argument: " + name + "(x)");
      if (fn != Functions().end()) {
        static const std::map<std::string, std::string> kArgs = {
            {"atan2", "(y, x)"}, {"min", "(a, b)"}, {"max", "(a, b)"}, {"mod", "(x, p)"}, {"clamp", "(x, a, b)"}};
        const auto args = kArgs.find(name);
        Fail(start, "the function " + name + " needs its argument" + (fn->second > 1 ? "s" : "") + ": " + name +
                        (args == kArgs.end() ? "(x)" : args->second));
      }
      if (!names_.count(name)) {
        if (pending_)
          for (size_t k = 0; k < pending_->size(); ++k)
            if ((*pending_)[k].first == name)
              Fail(start, k == 0 ? "'" + name + "' is the parameter being defined; a derived parameter cannot use itself"
                                 : "'" + name + "' is a parameter defined further down (line " +
                                       std::to_string((*pending_)[k].second.line) +
                                       "); a derived parameter may use only the parameters above it: move it below '" +
                                       name + "'");
        std::string known;
        for (const auto& n : names_) known += (known.empty() ? "" : ", ") + n;
        Fail(start, "unknown name '" + name + "' (known: " + known + ")");
      }
      if (name == "Pi") return {true, M_PI};
      if (name == "deg") return {true, mechgen::internal::kDegToRad};  // (io/format.h: M_PI / 180)
      return {false, 0.0};
    }
    if (c == ')') Fail(i_, "unexpected ')'; expected a number, a name or '('");
    Fail(i_, "unexpected " + CharText(c) + "; expected a number, a name or '('");
  }
  double Number() {
    const size_t start = i_;
    auto digits = [&] {
      const size_t from = i_;
      while (i_ < t_.size() && std::isdigit(static_cast<unsigned char>(t_[i_]))) ++i_;
      return i_ - from;
    };
    size_t n = digits();
    if (i_ < t_.size() && t_[i_] == '.') ++i_, n += digits();
    if (n == 0) Fail(start, "a '.' that is not part of a number");
    if (i_ < t_.size() && (t_[i_] == 'e' || t_[i_] == 'E')) {
      ++i_;
      if (i_ < t_.size() && (t_[i_] == '+' || t_[i_] == '-')) ++i_;
      const size_t exponent_start = i_;
      if (digits() == 0) Fail(start, "a number with an exponent but no exponent digits");
      // GiNaC's reader builds 10^exponent exactly, even for a mantissa of 0 (0e308308045).
      const std::string exponent = t_.substr(exponent_start, i_ - exponent_start);
      if (exponent.size() > 4 || std::stoi(exponent) > 400)
        Fail(start, "a number whose exponent (e" + (exponent.size() > 12 ? exponent.substr(0, 12) + "..." : exponent) +
                        ") is beyond 400 in magnitude");
    }
    if (i_ < t_.size() && (IsNameChar(t_[i_]) || t_[i_] == '.'))
      Fail(i_, "unexpected " + CharText(t_[i_]) + " right after a number (write 2*b for a product)");
    const std::string literal = t_.substr(start, i_ - start);
    const double v = std::strtod(literal.c_str(), nullptr);
    if (v != 0 ? !(std::abs(v) >= kMinMagnitude && std::abs(v) <= kMaxMagnitude) : literal.substr(0, literal.find_first_of("eE")).find_first_of("123456789") != std::string::npos)
      Fail(start, "the number " + literal + " is outside the range of model numbers (0, or 1e-100 to 1e100 in magnitude)");
    return v;
  }

  const std::string& t_;
  const std::set<std::string>& names_;
  const std::set<std::string>* tables_;
  const std::vector<std::pair<std::string, SourceMark>>* pending_;
  size_t i_ = 0;
  int depth_ = 0;
};

std::string Short(const GiNaC::ex& e) {
  std::ostringstream os;
  os << e;
  std::string s = os.str();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}


// The value of `e` at the defaults, after checking its sub-expressions bottom-up: every one
// finite and real, no division by zero, no even root or logarithm of a negative number, no
// asin or acos beyond [-1, 1]. Throws ExpressionFailure (offset unused) with the problem.
double CheckedValue(const GiNaC::ex& e, const GiNaC::exmap& defaults) {
  std::vector<double> args;
  for (size_t k = 0; k < e.nops(); ++k) args.push_back(CheckedValue(e.op(k), defaults));
  auto fail = [&](const std::string& why) -> void { throw ExpressionFailure{0, why}; };
  if (GiNaC::is_a<GiNaC::power>(e) && args.size() == 2) {
    const GiNaC::ex x = e.op(1);
    const bool integer = args[1] == std::floor(args[1]);  // pow(negative, integer) is defined
    if (args[0] == 0 && args[1] < 0) fail("divides by zero: " + Short(e.op(0)) + " = 0");
    if (args[0] < 0 && !integer)
      fail(std::string(x == GiNaC::numeric(1, 2) ? "takes the square root" : "takes a non-integer power") +
           " of a negative number: " + Short(e.op(0)) + " = " + G(args[0]));
  }
  if (GiNaC::is_a<GiNaC::function>(e)) {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    if (name == "log" && args.size() == 1 && !(args[0] > 0))
      fail("takes the logarithm of " + std::string(args[0] == 0 ? "zero" : "a negative number") + ": " + Short(e.op(0)) +
           " = " + G(args[0]));
    if ((name == "asin" || name == "acos") && args.size() == 1 && std::abs(args[0]) > 1)
      fail("takes " + name + " of a number beyond [-1, 1]: " + Short(e.op(0)) + " = " + G(args[0]));
    if (name == "atan2" && args.size() == 2 && args[0] == 0 && args[1] == 0)
      fail("takes atan2(0, 0), which has no angle: " + Short(e));
    if (name == "mmod" && args.size() == 2 && !(args[1] > 0))
      fail("takes mod(x, p) with a period p that is not positive: " + Short(e.op(1)) + " = " + G(args[1]));
  }
  GiNaC::ex v;
  try {
    v = e.subs(defaults).evalf();
  } catch (const std::exception& err) {
    std::string why = err.what();
    why = why.substr(0, why.find('\n'));
    fail("cannot be evaluated: " + Short(e) + " (" + why + ")");
  }
  if (!GiNaC::is_a<GiNaC::numeric>(v)) fail("does not evaluate to a number: " + Short(e));
  const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(v);
  double d = 0;
  try {
    // evalf rounds: (-1)^(d - 2) at d = 4 comes out as 1 + 1e-19 I.
    const double re = GiNaC::real(n).to_double(), im = GiNaC::imag(n).to_double();
    if (!(std::abs(im) <= 1e-12 * std::max(1.0, std::abs(re)))) fail("is not real: " + Short(e) + " = " + Short(v));
    d = re;
  } catch (const std::exception&) {
    d = NAN;
  }
  if (!std::isfinite(d) || std::abs(d) > 1e300) fail("is not finite or beyond 1e300: " + Short(e) + " = " + Short(v));
  return d;
}

}  // namespace

void SectionReader::FailAt(const YAML::Node& node, const std::string& text, size_t offset,
                           const std::string& message) const {
  m_.Fail(MarkAt(node, text, offset), message);
}

SourceMark SectionReader::MarkAt(const YAML::Node& node, const std::string& text, size_t offset) const {
  SourceMark mark = MarkOf(node);
  const YAML::Mark ym = node.Mark();
  if (source_ && !ym.is_null() && ym.pos >= 0 && static_cast<size_t>(ym.pos) < source_->size() &&
      text.find('\n') == std::string::npos) {
    const size_t pos = static_cast<size_t>(ym.pos);
    const char c = (*source_)[pos];
    const size_t skip = c == '"' || c == '\'' ? 1 : 0;
    if (source_->compare(pos + skip, text.size(), text) == 0) mark.column += static_cast<int>(skip + offset);
  }
  return mark;
}

GiNaC::ex SectionReader::Expression(const YAML::Node& node, const std::string& what, const GiNaC::symbol* u) const {
  GiNaC::symtab extra;
  if (u) extra["u"] = *u;
  return Expression(node, what, extra);
}

GiNaC::ex SectionReader::Expression(const YAML::Node& node, const std::string& what, const GiNaC::symtab& extra) const {
  const std::string text = Scalar(node, what);
  std::set<std::string> names = {"deg", "Pi"};
  for (const auto& [name, value] : extra) names.insert(name);
  for (const auto& p : m_.params) names.insert(p.name);
  for (const auto& d : m_.derived) names.insert(d.name);
  const std::string fix = "; see Expressions in models/README.md";
  const std::string shown = text.size() > 80 ? text.substr(0, 77) + "..." : text;
  std::set<std::string> tables;
  for (const Table& t : m_.tables) tables.insert(t.name);
  try {
    ExpressionSyntax(text, names, tables_ ? &tables : nullptr, pending_.empty() ? nullptr : &pending_).Check();
  } catch (const ExpressionFailure& f) {
    FailAt(node, text, f.offset, what + ": cannot read '" + shown + "' as an expression: " + f.message + fix);
  }
  GiNaC::symtab table;
  for (const auto& p : m_.params) table[p.name] = p.symbol;
  for (const auto& d : m_.derived) table[d.name] = d.value;  // inlined: no symbol of its own
  table["deg"] = GiNaC::Pi / 180;
  for (const auto& [name, value] : extra) table[name] = value;
  // A table call name(x) is read as mtable(index, 0, x).
  std::string parsed = text;
  // (GiNaC's default reader knows every registered function, mtable too; the syntax check
  // above admits only the language's functions and, in loads, the model's tables.)
  if (tables_)
    for (size_t i = 0; i < m_.tables.size(); ++i)
      parsed = std::regex_replace(parsed, std::regex("(^|[^A-Za-z0-9_])" + m_.tables[i].name + "\\s*\\("),
                                  "$1mtable(" + std::to_string(i) + ", 0, ");
  GiNaC::parser reader(table, /*strict=*/true, ExpressionReader());
  GiNaC::ex e;
  try {
    e = reader(parsed);
  } catch (const std::exception& err) {  // e.g. GiNaC's own evaluation: 1/0
    std::string why = err.what();
    why = why.substr(0, why.find('\n'));
    const auto internal = why.find("GiNaC: parse error");
    if (internal != std::string::npos) why = "GiNaC cannot parse it";
    if (why.find("division by zero") != std::string::npos) why = "it divides by zero";
    FailAt(node, text, 0, what + ": cannot read '" + shown + "' as an expression: " + why + fix);
  }
  bool uses_extra = e.has(mtable(GiNaC::wild(0), GiNaC::wild(1), GiNaC::wild(2)));  // tables: not evaluated here
  for (const auto& [name, value] : extra) uses_extra |= e.has(value);
  if (!uses_extra) {
    try {
      (void)CheckedValue(e, m_.Defaults());
    } catch (const ExpressionFailure& f) {
      FailAt(node, text, 0, what + ": '" + shown + "' " + f.message +
                                " at the parameters' defaults; change the expression or the defaults");
    }
  } else if (!e.info(GiNaC::info_flags::real) && e.has(GiNaC::I)) {
    Fail(node, what + ": '" + text + "' is not real");
  }
  return e;
}

double SectionReader::Number(const YAML::Node& node, const std::string& what) const {
  return ValueAtDefaults(m_, Expression(node, what), MarkOf(node), what);
}

PointRef SectionReader::Point(const YAML::Node& node, const std::string& what) const {
  const std::string text = Scalar(node, what);
  const auto dot = text.find('.');
  if (dot == std::string::npos) Fail(node, what + ": '" + text + "' must name a link point as link.point");
  const std::string link = text.substr(0, dot), point = text.substr(dot + 1);
  for (size_t i = 0; i < m_.links.size(); ++i) {
    if (m_.links[i].name != link) continue;
    const int k = m_.links[i].FindPoint(point);
    if (k < 0) {
      std::string list;
      for (const auto& pt : m_.links[i].points) list += (list.empty() ? "" : ", ") + pt.name;
      Fail(node, what + ": link '" + link + "' has no point '" + point + "'; its points are: " + list);
    }
    return {static_cast<int>(i), k};
  }
  std::string list;
  for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
  Fail(node, what + ": unknown link '" + link + "'; the links are: " + list);
}

PointRef SectionReader::ContactPoint(const YAML::Node& node) const {
  if (!node.IsScalar()) return {};
  const std::string text = node.as<std::string>();
  const auto dot = text.find('.');
  if (dot == std::string::npos || text.substr(dot + 1) != "contact") return {};
  for (size_t k = 0; k < m_.joints.size(); ++k)
    if (m_.joints[k].name == text.substr(0, dot) && m_.joints[k].type() == JointType::kRoll)
      return {m_.joints[k].link_b, -1, static_cast<int>(k)};
  return {};
}

int SectionReader::LinkIndex(const YAML::Node& node, const std::string& what) const {
  const std::string text = Scalar(node, what);
  for (size_t i = 0; i < m_.links.size(); ++i)
    if (m_.links[i].name == text) return static_cast<int>(i);
  std::string list;
  for (const auto& l : m_.links) list += (list.empty() ? "" : ", ") + l.name;
  Fail(node, what + ": unknown link '" + text + "'; the links are: " + list);
}

SourceMark SectionReader::KeyMark(const YAML::Node& value) const {
  auto it = keymarks_.find(value.Mark().pos);
  return it == keymarks_.end() ? MarkOf(value) : it->second;
}

Model LoadModel(const std::string& path, const std::string& name_override) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st))
    throw ModelError(path, {}, "cannot open the model file (" + (ec ? ec.message() : "no such file") + "); check the path");
  if (fs::is_directory(st)) throw ModelError(path, {}, "the path is a directory, not a model file; give the path of a .yaml file");
  if (!fs::is_regular_file(st))
    throw ModelError(path, {}, "the path is not a regular file (a device, a pipe or a socket); give the path of a .yaml file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelError(path, {}, "cannot open the model file (permission denied?); check the path");
  // Read at most one byte more than the limit: a file that grows while read is bounded too.
  std::string text(kMaxModelBytes + 1, '\0');
  in.read(&text[0], static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  if (text.size() > kMaxModelBytes)
    throw ModelError(path, {}, "is larger than " + std::to_string(kMaxModelBytes >> 20) +
                                   " MiB, the limit for a model file; a model is a short text");
  return LoadModelFromString(text, path, name_override);
}

namespace {

// Rejects what yaml-cpp reads but a model does not use: anchors and aliases (a value is
// written where it is used), and a second document.
class YamlFeatures : public YAML::EventHandler {
 public:
  explicit YamlFeatures(const Model& m) : m_(m) {}
  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1)
      m_.Fail(Mark(mark), "a second YAML document; a model file holds one: remove the '---' and what follows");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Anchor(mark, anchor); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    m_.Fail(Mark(mark), "YAML aliases (*name) are not supported; write the value where it is used");
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    Anchor(mark, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    Anchor(mark, anchor);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, YAML::EmitterStyle::value) override {
    Anchor(mark, anchor);
  }
  void OnMapEnd() override {}

 private:
  static SourceMark Mark(const YAML::Mark& mark) { return {mark.line + 1, mark.column + 1}; }
  void Anchor(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor)
      m_.Fail(Mark(mark), "YAML anchors (&name) are not supported; write each value where it is used");
  }
  const Model& m_;
  int documents_ = 0;
};

}  // namespace

Model LoadModelFromString(const std::string& text, const std::string& path,
                          const std::string& name_override) {
  Model m;
  m.file = path;
  if (text.size() > kMaxModelBytes)
    m.Fail({}, "is larger than " + std::to_string(kMaxModelBytes >> 20) + " MiB, the limit for a model file");
  YAML::Node root;
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    YamlFeatures features(m);
    while (parser.HandleNextDocument(features)) {
    }
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    m.Fail({e.mark.line + 1, e.mark.column + 1}, "YAML syntax: " + e.msg + "; fix the file's syntax");
  }
  if (!root || !root.IsMap()) m.Fail({1, 1}, "a model file is a YAML mapping (name:, links:, ...)");
  SectionReader r(&m);
  r.SetSource(&text);
  const auto entries = r.Entries(root, "the model", &ModelKeys());
  const YAML::Node& const_root = root;  // const lookups never insert keys
  auto get = [&](const std::string& key) { return const_root[key]; };
  try {
    if (YAML::Node n = get("name")) {
      m.name = r.Scalar(n, "name");
      CheckName(m, m.name, NameRole::kModel, MarkOf(n));
    }
    if (!name_override.empty()) {
      const std::string why = NameProblem(name_override, NameRole::kModel);
      if (!why.empty()) m.Fail({}, "--name '" + name_override + "' " + why + "; give a C++ identifier");
      m.name = name_override;
    }
    if (m.name.empty()) m.Fail({1, 1}, "the model has no name; add name: <identifier>");
    auto text_of = [&](const char* key, bool multiline) {
      YAML::Node n = get(key);
      if (!n) return std::string();
      const std::string t = r.Scalar(n, key);
      const std::string why = FreeTextProblem(t, multiline);
      if (!why.empty())
        r.Fail(n, std::string(key) + " " + why + ", and is copied into the generated header's comments; remove it");
      return t;
    };
    m.title = text_of("title", false);
    m.description = text_of("description", true);
    ReadParameters(r, get("parameters"));
    ReadLinks(r, get("links"));
    ReadJoints(r, get("joints"));
    ReadInputs(r, get("inputs"));
    ReadGravity(r, get("gravity"));
    ReadTables(r, get("tables"));
    ReadLoads(r, get("loads"));
    ReadSprings(r, get("springs"));
    ReadFriction(r, get("friction"));
    ReadDampers(r, get("dampers"));
    ReadOutputs(r, get("outputs"));
    ReadDesign(r, get("design"));
    CheckDynamicRefs(m);
    ReadAssembly(r, get("assembly"));
    ReadAssemblyModes(r, get("assembly_modes"));
  } catch (const YAML::Exception& e) {  // e.g. a conversion yaml-cpp refuses
    m.Fail({e.mark.line + 1, e.mark.column + 1}, e.msg);
  }
  // Parameters, links and joints have a namespace each (a joint `ram` beside a link `ram`):
  // in the generated C++ a parameter is a member of Params, a link's name only ever appears
  // in theta_<link> and in strings, a joint's in s_/psi_/u_<joint>, in reaction names
  // (F_<joint>_x, ...) and in the functions of cams (CamLaw_<joint>, ...): no two of them
  // can meet (the CSV columns are checked apart, CheckCsvColumnNames). The one reference
  // that could name either is a point: `<rolling joint>.contact` against a link of that
  // name with a point `contact`.
  for (const Joint& j : m.joints) {
    if (j.type() != JointType::kRoll) continue;
    for (const Link& l : m.links) {
      const int k = l.name == j.name ? l.FindPoint("contact") : -1;
      if (k >= 0)
        m.Fail(l.points[k].mark, "'" + j.name + ".contact' would name both this point of link '" + l.name +
                                     "' and the contact point of rolling joint '" + j.name +
                                     "'; rename the point, the link or the joint");
    }
  }
  return m;
}

}  // namespace mechgen
