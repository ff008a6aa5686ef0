#pragma once

#include <sys/resource.h>
#include <unistd.h>
#include <QCoreApplication>
#include <QThread>
#include <QThreadPool>
#include <QtConcurrent/QtConcurrentRun>

#include <utility>

namespace ambler::gs {

// Work that only feeds a view (a simulated scan or tray, a rock fit, a
// mesh, a path, a registration, opening a log) runs on a pool thread at
// nice 10: it waits while the GUI thread and the 3-D views' renderers
// (nice 5) need the two cores, yet keeps a share of them, so that a lock
// it holds is soon let go, malloc's above all (one arena for every
// thread). At SCHED_IDLE (Qt's IdlePriority) such a holder starved behind
// the renderers while the GUI thread waited on it (docs/ARCHITECTURE.md,
// Threads). The OpenMP threads it starts inherit the nice value.
inline void runAtBackgroundPriority() { setpriority(PRIO_PROCESS, id_t(gettid()), 10); }

// A thread waiting on a job not yet started runs it itself (Qt's
// QFuture::waitForFinished): the GUI thread, or whichever thread handed it
// over, keeps its priority then, since nice cannot be raised back without
// privileges.
template <typename F>
auto runInBackground(QThreadPool* pool, F&& f) {
  return QtConcurrent::run(pool,
                           [f = std::forward<F>(f), from = QThread::currentThread()]() mutable {
                             const auto* app = QCoreApplication::instance();
                             const QThread* here = QThread::currentThread();
                             if (here != from && !(app && here == app->thread()))
                               runAtBackgroundPriority();
                             return f();
                           });
}

template <typename F>
auto runInBackground(F&& f) {
  return runInBackground(QThreadPool::globalInstance(), std::forward<F>(f));
}

}  // namespace ambler::gs
