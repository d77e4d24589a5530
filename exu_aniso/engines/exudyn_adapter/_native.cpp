// Native force callbacks: Exudyn calls the compiled contact kernel without entering Python.
//
// Exudyn stores an ObjectGenericODE2's forceUserFunction as a std::function of the signature
//     std::vector<double>(const MainSystem&, double t, int itemNumber, std::vector<double> q,
//                         std::vector<double> q_t)
// converted from the Python object it is given by pybind11's std::function caster. When that object
// is a pybind11 function of exactly this signature without state, the caster takes the raw C++
// function pointer out of it: Exudyn then calls ``force`` below directly, with no Python frame, no
// list conversion and no reference counting. ``force`` looks up the contact set registered for
// (the system's address, itemNumber) and calls its kernel: a numba cfunc
// (exu_aniso.kernel.native) over the set's compiled arguments, stored once in memory.
//
// The same for the Jacobian (``jacobian``, Exudyn's type
//     py::object(const MainSystem&, double t, int itemNumber, std::vector<double> q,
//                std::vector<double> q_t, double fODE2, double fODE2_t)):
// the kernel writes the set's Jacobian (times fODE2 and fODE2_t) into its own array, which is
// returned as the same Python object every time (a numpy array, or a scipy CSR matrix over the
// blocks' memory for a group); Exudyn copies it.
//
// The same for the system's post-Newton function (``post_newton``, Exudyn's type
//     std::array<double, 2>(const MainSystem&, double t)):
// when every contact set of the system is native and armed, it commits each set's history
// candidate by the compiled stage kernel (exu_aniso.kernel.native.stage_kernel) and moves the sets'
// start of step on; anything else (a set not armed, a candidate not at the converged state, an
// unresolved step) goes to the system's Python post-Newton function, which does it all.
//
// What Python still does (exu_aniso.engines.exudyn_adapter.contact_set and .commit): a call that is not inside a
// time step that Python has checked goes to the set's Python ``delegate`` instead (the first call
// of every solve: Exudyn's initial accelerations; a call at or before the start of the step, as
// after a restart or a rejected step; a call after a disarm). The delegate checks the views of
// Exudyn's vectors (a re-assembly may have moved them), stores the kernel's arguments again if
// needed, evaluates the call and arms the set with the start time of the step. A kernel that
// raises (an ill-posed contact state) returns ERROR; the call is then repeated by the delegate,
// which raises the error with its message.
//
// Only the names of Exudyn's types matter here (the function type must be Exudyn's, for the
// caster): MainSystem is declared, never used. No Exudyn header, no link to Exudyn.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <climits>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;

class MainSystem {};                 // Exudyn's system class: its name makes the function type
using StdVector = std::vector<double>;

// the set kernel: (block address, mode, dt [s], q, q_t, n, fODE2, fODE2_t) -> status of the set
using Kernel = int64_t (*)(int64_t, int64_t, double, const double*, const double*, int64_t, double, double);

static const int64_t KERNEL_ERROR = -1000;   // the kernel raised (see exu_aniso.kernel.native)

// the stage kernel: (stage block address) -> 0 written, else not (exu_aniso.kernel.sets.stage_candidate)
using Stage = int64_t (*)(int64_t);
static Stage stage_kernel = nullptr;

// clock (a float64 array of the set, CLOCK_* entries): start time of the step [s], armed flag,
// end time of the solve [s], the longest step taken natively [s] (a call farther from the start of the
// step belongs to a new solve that starts later: Python checks it)
static const int CLOCK_START = 0, CLOCK_ARMED = 1, CLOCK_END = 2, CLOCK_STEP = 3;

struct Entry {
    Kernel kernel = nullptr;
    int64_t block = 0;               // address of the kernel's stored arguments
    int64_t stage = 0;               // address of the stage kernel's stored arguments
    const double* Q = nullptr;       // the generalized force the kernel writes (n,)
    int64_t n = 0;                   // the contact object's coordinates
    double* clock = nullptr;
    py::object delegate;             // Python: delegate(t, q, q_t) evaluates into Q; delegate.jacobian(t, q,
                                     // q_t, fODE2, fODE2_t) returns the Jacobian
    py::object J;                    // the Jacobian the kernel writes (its Python object)
    long native_calls = 0;
    long delegated_calls = 0;
    long native_jacobians = 0;
    long delegated_jacobians = 0;
};

using Key = std::pair<uintptr_t, int>;
// never destroyed: its Python references must not be released after the interpreter has finalized
static std::map<Key, Entry>& registry = *new std::map<Key, Entry>();

struct System {
    py::object fallback;             // Python: fallback(t) -> [discontinuous error, step size], commit.post_newton
    long native_calls = 0;
    long python_calls = 0;
};
// one entry per system that had all its sets native (a few bytes; replaced when a system at the same
// address registers, and used only by a system whose post-Newton function is post_newton)
static std::map<uintptr_t, System>& systems = *new std::map<uintptr_t, System>();

// the set registered for (mbs, itemNumber), its coordinates checked against q, q_t; what: the caller's name
static Entry& lookup(const MainSystem& mbs, int itemNumber, const StdVector& q, const StdVector& q_t,
                     const char* what) {
    auto it = registry.find(Key(reinterpret_cast<uintptr_t>(&mbs), itemNumber));
    if (it == registry.end()) {
        throw std::runtime_error(std::string("exu_aniso native ") + what + ": contact object " +
                                 std::to_string(itemNumber) + " of this system has no registered contact set "
                                 "(CreateAnisotropicContact registers it)");
    }
    Entry& e = it->second;
    if (static_cast<int64_t>(q.size()) != e.n || static_cast<int64_t>(q_t.size()) != e.n) {
        throw std::runtime_error(std::string("exu_aniso native ") + what + ": contact object " +
                                 std::to_string(itemNumber) + " got " + std::to_string(q.size()) +
                                 " coordinates, registered with " + std::to_string(e.n));
    }
    return e;
}

// the kernel in mode (0: force into Q, 1: Jacobian into J) if the set is armed and t is inside its step;
// false if the call must go to Python
static bool call_kernel(Entry& e, int64_t mode, double t, const StdVector& q, const StdVector& q_t, double fODE2,
                        double fODE2_t) {
    if (e.clock[CLOCK_ARMED] == 0.0 || !(t > e.clock[CLOCK_START]) || t - e.clock[CLOCK_START] > e.clock[CLOCK_STEP])
        return false;
    return e.kernel(e.block, mode, t - e.clock[CLOCK_START], q.data(), q_t.data(), e.n, fODE2, fODE2_t) !=
           KERNEL_ERROR;
}

static StdVector force(const MainSystem& mbs, double t, int itemNumber, StdVector q, StdVector q_t) {
    Entry& e = lookup(mbs, itemNumber, q, q_t, "force");
    if (call_kernel(e, 0, t, q, q_t, 0.0, 0.0)) {
        e.native_calls++;
    } else {
        e.delegated_calls++;
        e.delegate(t, q, q_t);       // raises (pybind11 passes the Python error on to Exudyn)
    }
    return StdVector(e.Q, e.Q + e.n);
}

static py::object jacobian(const MainSystem& mbs, double t, int itemNumber, StdVector q, StdVector q_t,
                           double fODE2, double fODE2_t) {
    Entry& e = lookup(mbs, itemNumber, q, q_t, "jacobian");
    if (call_kernel(e, 1, t, q, q_t, fODE2, fODE2_t)) {
        e.native_jacobians++;
        return e.J;
    }
    e.delegated_jacobians++;
    return e.delegate.attr("jacobian")(t, q, q_t, fODE2, fODE2_t);
}

static std::array<double, 2> post_newton(const MainSystem& mbs, double t) {
    const uintptr_t a = reinterpret_cast<uintptr_t>(&mbs);
    auto sys = systems.find(a);
    if (sys == systems.end()) {
        throw std::runtime_error("exu_aniso native post-Newton: this system has no registered contact sets");
    }
    const auto first = registry.lower_bound(Key(a, INT_MIN));
    bool native = stage_kernel != nullptr;
    for (auto it = first; native && it != registry.end() && it->first.first == a; ++it) {
        const double* c = it->second.clock;
        native = c[CLOCK_ARMED] != 0.0 && t > c[CLOCK_START];
    }
    for (auto it = first; native && it != registry.end() && it->first.first == a; ++it) {
        native = stage_kernel(it->second.stage) == 0;
    }
    if (!native) {                   // Python commits every set (a set written above is written again)
        sys->second.python_calls++;
        return sys->second.fallback(t).cast<std::array<double, 2>>();
    }
    for (auto it = first; it != registry.end() && it->first.first == a; ++it) {
        double* c = it->second.clock;    // the step is accepted: the next one starts at t
        const double h = t - c[CLOCK_START];
        c[CLOCK_START] = t;
        if (t + 0.5 * h >= c[CLOCK_END]) c[CLOCK_ARMED] = 0.0;   // the solve's last step
    }
    sys->second.native_calls++;
    return {0.0, -1.0};
}

// The address of the C++ object behind a pybind11 instance (Exudyn's MainSystem): the value
// pointer of pybind11's instance record, the address Exudyn passes to force as ``&mbs``.
static uintptr_t instance_address(py::handle obj) {
    auto* inst = reinterpret_cast<py::detail::instance*>(obj.ptr());
    if (!py::isinstance(obj, py::module_::import("exudyn").attr("MainSystem"))) {
        throw std::invalid_argument("exu_aniso native: expected an exudyn.MainSystem");
    }
    void* p = inst->simple_layout ? inst->simple_value_holder[0] : inst->nonsimple.values_and_holders[0];
    return reinterpret_cast<uintptr_t>(p);
}

PYBIND11_MODULE(_native, m) {
    m.doc() = "Native force callbacks for Exudyn: the compiled contact kernel without Python (see _native.cpp)";
    m.attr("KERNEL_ERROR") = KERNEL_ERROR;
    m.attr("CLOCK_START") = CLOCK_START;
    m.attr("CLOCK_ARMED") = CLOCK_ARMED;
    m.attr("CLOCK_END") = CLOCK_END;
    m.attr("CLOCK_STEP") = CLOCK_STEP;
    m.def("force", &force, "the forceUserFunction to give Exudyn's ObjectGenericODE2");
    m.def("jacobian", &jacobian, "the jacobianUserFunction to give Exudyn's ObjectGenericODE2");
    m.def("post_newton", &post_newton, "the post-Newton function to give mbs.SetPostNewtonUserFunction");
    m.def("set_stage_kernel", [](uintptr_t kernel) { stage_kernel = reinterpret_cast<Stage>(kernel); },
          "the stage kernel's address (exu_aniso.kernel.native.stage_kernel)");
    m.def("register_system",
          [](py::handle mbs, py::object fallback) {
              System s;
              s.fallback = std::move(fallback);
              systems[instance_address(mbs)] = std::move(s);
          },
          "register the Python post-Newton function of a system whose contact sets are all native");
    m.def("post_newton_calls",
          [](uintptr_t system) {
              auto it = systems.find(system);
              if (it == systems.end()) return py::make_tuple(0, 0);
              return py::make_tuple(it->second.native_calls, it->second.python_calls);
          },
          "(native, Python) post-Newton calls of a system");
    m.def("system_address", &instance_address, "address of the C++ MainSystem behind an exudyn.MainSystem");
    m.def("call_force",
          [](py::handle mbs, int item, double t, const StdVector& q, const StdVector& q_t, long calls) {
              const auto* system = reinterpret_cast<const MainSystem*>(instance_address(mbs));
              StdVector Q;
              for (long i = 0; i < calls; ++i) Q = force(*system, t, item, q, q_t);   // by value, as Exudyn passes them
              return Q;
          },
          "call the native force of (mbs, item) calls times as Exudyn calls it (benchmarks); returns the last Q");
    m.def("call_jacobian",
          [](py::handle mbs, int item, double t, const StdVector& q, const StdVector& q_t, double fODE2,
             double fODE2_t) {
              const auto* system = reinterpret_cast<const MainSystem*>(instance_address(mbs));
              return jacobian(*system, t, item, q, q_t, fODE2, fODE2_t);
          },
          "call the native Jacobian of (mbs, item) once as Exudyn calls it (tests); returns what it returns");
    m.def("register_set",
          [](py::handle mbs, int item, uintptr_t kernel, int64_t block, int64_t stage, uintptr_t Q, int64_t n,
             uintptr_t clock, py::object delegate, py::object J) {
              Entry e;
              e.kernel = reinterpret_cast<Kernel>(kernel);
              e.block = block;
              e.stage = stage;
              e.Q = reinterpret_cast<const double*>(Q);
              e.n = n;
              e.clock = reinterpret_cast<double*>(clock);
              e.delegate = std::move(delegate);
              e.J = std::move(J);
              registry[Key(instance_address(mbs), item)] = std::move(e);
          },
          "register a contact set's kernel for (mbs, itemNumber), replacing an earlier one");
    m.def("release_set",
          [](uintptr_t system, int item, int64_t block) {
              auto it = registry.find(Key(system, item));
              if (it != registry.end() && it->second.block == block) registry.erase(it);
          },
          "forget the set registered for (system address, itemNumber) if it is still the one at block");
    m.def("calls",
          [](uintptr_t system, int item) {
              auto it = registry.find(Key(system, item));
              if (it == registry.end()) return py::make_tuple(0, 0);
              return py::make_tuple(it->second.native_calls, it->second.delegated_calls);
          },
          "(native, delegated) force calls of the set registered for (system address, itemNumber)");
    m.def("jacobian_calls",
          [](uintptr_t system, int item) {
              auto it = registry.find(Key(system, item));
              if (it == registry.end()) return py::make_tuple(0, 0);
              return py::make_tuple(it->second.native_jacobians, it->second.delegated_jacobians);
          },
          "(native, delegated) Jacobian calls of the set registered for (system address, itemNumber)");
    m.def("registered", []() { return registry.size(); }, "number of registered sets");
}
