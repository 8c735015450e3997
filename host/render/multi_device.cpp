#include "render/multi_device.h"

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace whitted {
namespace {

// Passes bands on to `sink` in band order: a renderer whose band is not the
// next one waits (its band stays in its read-back buffer meanwhile), so the
// host holds at most one band per device.
class OrderedSink {
public:
    explicit OrderedSink(BandSink& sink) : sink_(sink) {}

    void write(const BandView& band) {
        std::unique_lock lock(mutex_);
        turn_.wait(lock, [&] { return failed_ || next_ == band.index; });
        if (failed_) throw Abandoned{};
        sink_.writeBand(band);
        ++next_;
        turn_.notify_all();
    }
    // Another renderer failed: release everyone waiting.
    void fail() {
        std::lock_guard lock(mutex_);
        failed_ = true;
        turn_.notify_all();
    }
    struct Abandoned {};

private:
    BandSink& sink_;
    std::mutex mutex_;
    std::condition_variable turn_;
    int next_ = 0;
    bool failed_ = false;
};

class Port final : public BandSink {
public:
    explicit Port(OrderedSink& ordered) : ordered_(ordered) {}
    void writeBand(const BandView& band) override { ordered_.write(band); }

private:
    OrderedSink& ordered_;
};

}  // namespace

RenderResult renderOnDevices(std::span<Renderer* const> renderers, BandSink& sink, const ProgressCallback& progress) {
    if (renderers.size() == 1) return renderers[0]->renderTo(sink, progress);
    // One band layout for all: the smallest band any device allows.
    uint32_t rows = UINT32_MAX;
    for (Renderer* r : renderers) rows = std::min(rows, r->bandRows());
    for (Renderer* r : renderers) r->limitBandRows(rows);

    OrderedSink ordered(sink);
    std::vector<RenderResult> results(renderers.size());
    std::vector<double> done(renderers.size(), 0.0);
    std::vector<std::exception_ptr> errors(renderers.size());
    std::mutex progressMutex;
    std::vector<std::thread> threads;
    for (size_t i = 0; i < renderers.size(); ++i)
        threads.emplace_back([&, i] {
            Port port(ordered);
            try {
                results[i] = renderers[i]->renderTo(
                    port,
                    [&](double f) {
                        std::lock_guard lock(progressMutex);
                        done[i] = f;
                        double sum = 0;
                        for (double d : done) sum += d;
                        if (progress) progress(sum / double(done.size()));
                    },
                    uint32_t(i), uint32_t(renderers.size()));
            } catch (const OrderedSink::Abandoned&) {
            } catch (...) {
                errors[i] = std::current_exception();
                ordered.fail();
            }
        });
    for (std::thread& t : threads) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);

    // The statistics of all devices together; times are the longest.
    RenderResult total = results[0];
    for (size_t i = 1; i < results.size(); ++i) {
        const RenderResult& r = results[i];
        total.rays.primary += r.rays.primary;
        total.rays.shadow += r.rays.shadow;
        total.rays.secondary += r.rays.secondary;
        total.samplesTaken += r.samplesTaken;
        total.lostSamples += r.lostSamples;
        total.bands += r.bands;
        total.deviceBytes += r.deviceBytes;
        total.renderSeconds = std::max(total.renderSeconds, r.renderSeconds);
        total.uploadSeconds = std::max(total.uploadSeconds, r.uploadSeconds);
        total.pipelineSeconds = std::max(total.pipelineSeconds, r.pipelineSeconds);
    }
    return total;
}

}  // namespace whitted
