//! GPU timing: timestamp queries written outside render passes (lavapipe reads near zero
//! inside a dynamic-rendering pass), masked by `timestampValidBits` and scaled by
//! `timestampPeriod`, and pipeline statistics where the device has them. One `GpuTimer` holds
//! the queries of several frames in flight, so reading a finished frame never stalls the
//! next one.

use super::context::Context;
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// Pipeline statistics of one frame (counts of the whole frame's work).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct PipelineStatistics {
    pub input_assembly_vertices: u64,
    pub input_assembly_primitives: u64,
    pub vertex_shader_invocations: u64,
    pub tessellation_control_patches: u64,
    pub tessellation_evaluation_invocations: u64,
    pub clipping_invocations: u64,
    pub clipping_primitives: u64,
    pub fragment_shader_invocations: u64,
}

const STATISTICS: [vk::QueryPipelineStatisticFlags; 8] = [
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_VERTICES,
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::TESSELLATION_CONTROL_SHADER_PATCHES,
    vk::QueryPipelineStatisticFlags::TESSELLATION_EVALUATION_SHADER_INVOCATIONS,
];

/// When a pass ran on the GPU: nanoseconds on the device's timestamp clock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuInterval {
    pub start_ns: f64,
    pub end_ns: f64,
}

impl GpuInterval {
    pub fn milliseconds(&self) -> f64 {
        (self.end_ns - self.start_ns) * 1e-6
    }
}

/// Timestamps around passes and pipeline statistics, for `slots` frames in flight.
pub struct GpuTimer {
    context: Arc<Context>,
    timestamps: vk::QueryPool,
    statistics: Option<vk::QueryPool>,
    passes: u32,
    slots: u32,
}

impl GpuTimer {
    /// Room for `passes` timed passes per frame and `slots` frames in flight.
    pub fn new(context: &Arc<Context>, passes: u32, slots: u32) -> Result<GpuTimer> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2 * passes * slots);
        // SAFETY: valid create info; destroyed in `Drop`.
        let timestamps = unsafe { context.device.create_query_pool(&info, None) }
            .while_("creating the timestamp query pool")?;
        context.name(timestamps, "timestamps");
        let statistics = if context.features.pipeline_statistics {
            let flags = STATISTICS.iter().fold(vk::QueryPipelineStatisticFlags::empty(), |a, &b| a | b);
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::PIPELINE_STATISTICS)
                .pipeline_statistics(flags)
                .query_count(slots);
            // SAFETY: the feature is enabled; destroyed in `Drop`.
            let pool = unsafe { context.device.create_query_pool(&info, None) }
                .while_("creating the pipeline statistics query pool")?;
            context.name(pool, "pipeline statistics");
            Some(pool)
        } else {
            None
        };
        Ok(GpuTimer { context: context.clone(), timestamps, statistics, passes, slots })
    }

    /// Whether pipeline statistics are collected.
    pub fn has_statistics(&self) -> bool {
        self.statistics.is_some()
    }

    /// Resets the queries of frame `slot`; record before any other query command of it.
    pub fn reset(&self, cmd: vk::CommandBuffer, slot: u32) {
        let device = &self.context.device;
        // SAFETY: `cmd` is recording outside a render pass; the queries of this slot are not
        // in use by pending work (the caller waited for the slot's previous frame).
        unsafe {
            device.cmd_reset_query_pool(cmd, self.timestamps, 2 * self.passes * slot, 2 * self.passes);
            if let Some(pool) = self.statistics {
                device.cmd_reset_query_pool(cmd, pool, slot, 1);
            }
        }
    }

    /// Writes the start (`end == false`) or end timestamp of `pass` in frame `slot`. Call
    /// outside render passes.
    pub fn timestamp(&self, cmd: vk::CommandBuffer, slot: u32, pass: u32, end: bool) {
        let stage = if end { vk::PipelineStageFlags2::ALL_COMMANDS } else { vk::PipelineStageFlags2::NONE };
        self.write(cmd, stage, slot, pass, end);
    }

    /// `timestamp` at the top of the pipe, the end as well: the interval of work that did not
    /// run. lavapipe flushes its queued work for a timestamp of any later stage, which costs a
    /// frame that has nothing to time there.
    pub fn top_of_pipe_timestamp(&self, cmd: vk::CommandBuffer, slot: u32, pass: u32, end: bool) {
        self.write(cmd, vk::PipelineStageFlags2::TOP_OF_PIPE, slot, pass, end);
    }

    /// `timestamp`, but a start as well is written only once every earlier command has
    /// finished: the boundaries of back-to-back steps that barriers separate, where a start at
    /// the top of the pipe would come before the previous step's end. The caller records a
    /// barrier right after it, before any other work: lavapipe takes a timestamp's value when
    /// it next flushes its queued work, which a barrier does; with work between them, the time
    /// of the dispatches after a boundary showed up in the step before it (the refining step
    /// read 0.1 ms instead of 3).
    pub fn settled_timestamp(&self, cmd: vk::CommandBuffer, slot: u32, pass: u32, end: bool) {
        self.write(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, slot, pass, end);
    }

    /// Writes the start or end timestamp of `pass` in frame `slot` once `stage` of every
    /// earlier command has finished.
    fn write(&self, cmd: vk::CommandBuffer, stage: vk::PipelineStageFlags2, slot: u32, pass: u32, end: bool) {
        let query = self.query(slot, pass, end);
        // SAFETY: `cmd` is recording; the query was reset for this frame.
        unsafe { self.context.device.cmd_write_timestamp2(cmd, stage, self.timestamps, query) };
    }

    /// The timestamp query of the start or end of `pass` in frame `slot`.
    fn query(&self, slot: u32, pass: u32, end: bool) -> u32 {
        2 * (self.passes * slot + pass) + u32::from(end)
    }

    /// Starts (`begin == true`) or ends the statistics query of frame `slot`.
    pub fn statistics(&self, cmd: vk::CommandBuffer, slot: u32, begin: bool) {
        let Some(pool) = self.statistics else { return };
        // SAFETY: `cmd` is recording; begin and end pair up in the same command buffer.
        unsafe {
            if begin {
                self.context.device.cmd_begin_query(cmd, pool, slot, vk::QueryControlFlags::empty());
            } else {
                self.context.device.cmd_end_query(cmd, pool, slot);
            }
        }
    }

    /// When the first `passes` passes of frame `slot` ran, waiting for the results (each must
    /// have been written).
    pub fn pass_intervals(&self, slot: u32, passes: u32) -> Result<Vec<GpuInterval>> {
        debug_assert!(passes <= self.passes);
        let mut ticks = vec![0u64; 2 * passes as usize];
        // SAFETY: the range lies in the pool; WAIT blocks until the frame's queries finished.
        unsafe {
            self.context.device.get_query_pool_results(
                self.timestamps,
                2 * self.passes * slot,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .while_("reading timestamps")?;
        let bits = self.context.info.timestamp_valid_bits;
        let mask = if bits >= 64 { u64::MAX } else { (1u64 << bits) - 1 };
        let period = self.context.info.timestamp_period_ns as f64;
        Ok(ticks
            .chunks_exact(2)
            .map(|pair| {
                let start = pair[0] & mask;
                let elapsed = pair[1].wrapping_sub(start) & mask;
                let start_ns = start as f64 * period;
                GpuInterval { start_ns, end_ns: start_ns + elapsed as f64 * period }
            })
            .collect())
    }

    /// The pipeline statistics of frame `slot` (None without the feature), waiting for them.
    pub fn read_statistics(&self, slot: u32) -> Result<Option<PipelineStatistics>> {
        let Some(pool) = self.statistics else { return Ok(None) };
        let mut values = [0u64; 8];
        // SAFETY: one query of 8 counters (as many as flags) at `slot`; WAIT for completion.
        unsafe {
            self.context.device.get_query_pool_results(
                pool,
                slot,
                std::slice::from_mut(&mut values),
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .while_("reading pipeline statistics")?;
        // Results come in the order of the flag bits, lowest first.
        Ok(Some(PipelineStatistics {
            input_assembly_vertices: values[0],
            input_assembly_primitives: values[1],
            vertex_shader_invocations: values[2],
            clipping_invocations: values[3],
            clipping_primitives: values[4],
            fragment_shader_invocations: values[5],
            tessellation_control_patches: values[6],
            tessellation_evaluation_invocations: values[7],
        }))
    }

    pub fn slots(&self) -> u32 {
        self.slots
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        // SAFETY: the owner waits for the device before dropping the timer.
        unsafe {
            self.context.device.destroy_query_pool(self.timestamps, None);
            if let Some(pool) = self.statistics {
                self.context.device.destroy_query_pool(pool, None);
            }
        }
    }
}
