#!/usr/bin/env python3
"""Generator unit tests: how the classifier plans the tricky commands, and
that the generator refuses inconsistent annotation files."""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "codegen"))
import glcast_codegen  # noqa: E402

MODEL = glcast_codegen.Model()
PLANS = {p.cmd.name: p for p in MODEL.plans}


def wire(command, param):
    p = PLANS[command]
    return p.params[[q.name for q in p.cmd.params].index(param)]


class TrickyCommands(unittest.TestCase):
    def test_teximage_size_follows_pixel_store_and_unpack_buffer(self):
        w = wire("glTexImage2D", "pixels")
        self.assertEqual(w.kind, "in")
        self.assertEqual(w.len, "sz.image(Dir::In, format, type, width, height, 1)")
        self.assertEqual(w.source, "GL_PIXEL_UNPACK_BUFFER_BINDING")
        self.assertEqual(wire("glReadPixels", "pixels").kind, "out")
        self.assertIn("Dir::Out", wire("glReadPixels", "pixels").len)

    def test_enum_dependent_counts(self):
        self.assertEqual(wire("glLightfv", "params").len, "sz.pname_count(PnameTable::light, pname)")
        self.assertEqual(wire("glMaterialfv", "params").len, "sz.pname_count(PnameTable::material, pname)")
        g = wire("glGetFloatv", "data")
        self.assertEqual((g.kind, g.len), ("out", "sz.pname_count(PnameTable::get, pname)"))
        self.assertTrue(PLANS["glGetFloatv"].reply_only)
        # indexed glGet keys its table on `target`
        self.assertEqual(wire("glGetIntegeri_v", "data").len, "sz.pname_count(PnameTable::get_indexed, target)")

    def test_type_sized_and_string_arrays(self):
        self.assertEqual(wire("glCallLists", "lists").len, "sz.call_lists(n, type)")
        s = wire("glShaderSource", "string")
        self.assertEqual((s.kind, s.count, s.lengths), ("string_array", "count", "length"))

    def test_draw_elements_and_client_arrays(self):
        w = wire("glDrawElements", "indices")
        self.assertEqual((w.source, w.len), ("GL_ELEMENT_ARRAY_BUFFER_BINDING", "count * sz.type_bytes(type)"))
        self.assertEqual(PLANS["glDrawElements"].draw["indices"], "indices")
        self.assertEqual(wire("glVertexPointer", "pointer").kind, "deferred")
        self.assertEqual(wire("glMultiDrawElements", "indices").kind, "index_arrays")

    def test_outputs_and_handwritten(self):
        g = wire("glGenTextures", "textures")
        self.assertEqual((g.kind, g.len), ("out", "n"))
        m = PLANS["glMapBufferRange"]
        self.assertTrue(m.handwritten)
        self.assertEqual(m.ret.kind, "address")

    def test_aliases_inherit_annotations(self):
        self.assertEqual(wire("glPointParameterfvARB", "params").len,
                         "sz.pname_count(PnameTable::point_parameter, pname)")
        self.assertEqual(wire("glVertexAttribPointerARB", "pointer").kind, "deferred")

    def test_core_coverage_is_complete(self):
        core = [p for p in MODEL.plans if p.cmd.is_core]
        missing = [p.cmd.name for p in core if not p.serializable]
        self.assertEqual(missing, [])
        self.assertGreater(len(core), 1080)

    def test_opcodes_are_stable_registry_order(self):
        self.assertEqual([p.opcode for p in MODEL.plans], list(range(len(MODEL.plans))))
        self.assertEqual(MODEL.table_hash(), glcast_codegen.Model().table_hash())


def sem(command):
    return PLANS[command].sem


def replay_use(command, param):
    return next(a["use"] for a in PLANS[command].replay_params if a["name"] == param)


class DeclaredSemantics(unittest.TestCase):
    """semantics.yaml, as the generated command table will carry it."""

    def test_unaliased_twins_get_their_core_commands_meaning(self):
        self.assertEqual(sem("glBindFramebufferEXT")["twin"], "glBindFramebuffer")
        self.assertEqual(sem("glBindFramebufferEXT")["window"], "draw_framebuffer")
        self.assertEqual(sem("glBindFramebufferEXT")["window_params"], [0, 1])
        self.assertEqual(replay_use("glBindFramebufferEXT", "framebuffer"), "CreateAtFirstUse")
        self.assertTrue(sem("glDeleteTexturesEXT")["deletes"])
        self.assertEqual(replay_use("glDeleteTexturesEXT", "textures"), "Delete")
        # not_twins inherit nothing
        self.assertIsNone(sem("glPolygonOffsetEXT")["twin"])
        self.assertIsNone(sem("glPolygonOffsetEXT")["state"])

    def test_aliases_found_by_position_when_they_name_parameters_differently(self):
        self.assertEqual(sem("glUseProgramObjectARB")["program_use"], 0)
        self.assertEqual(sem("glCreateShaderObjectARB")["shader_type"], 0)
        self.assertEqual(PLANS["glBindBufferARB"].sem["redraw"], "state")

    def test_window_coordinates_of_every_viewport_and_scissor_form(self):
        self.assertEqual((sem("glViewport")["window"], sem("glViewport")["window_params"]), ("viewport", [0, 1, 2, 3]))
        self.assertEqual(sem("glViewportIndexedf")["window"], "viewport_indexed")
        self.assertEqual(sem("glViewportIndexedfv")["window_params"], [0, 1])
        self.assertEqual(sem("glViewportArrayv")["window"], "viewport_array")
        self.assertEqual(sem("glScissorIndexed")["window_params"], [0, 1, 2, 3, 4])
        self.assertEqual(sem("glScissorArrayv")["window"], "scissor_array")
        # (the destination first: the rectangle a tile maps; then the source, the mask, the filter)
        self.assertEqual((sem("glBlitFramebuffer")["window"], sem("glBlitFramebuffer")["window_params"]),
                         ("blit", [4, 5, 6, 7, 0, 1, 2, 3, 8, 9]))

    def test_matrix_and_redraw_kinds(self):
        self.assertEqual(sem("glLoadIdentity")["matrix"], "load")
        self.assertEqual(sem("glFrustum")["matrix"], "multiply")
        self.assertEqual(sem("glPushMatrix")["matrix"], "push")
        self.assertEqual(sem("glDrawElements")["redraw"], "draw")   # from commands.yaml draws
        self.assertEqual(sem("glRectf")["redraw"], "draw")
        self.assertEqual(sem("glVertexAttrib4f")["redraw"], "state")
        self.assertEqual(sem("glMultiTexCoord2fARB")["redraw"], "state")
        self.assertIsNone(sem("glVertexAttribLPointer")["redraw"])
        self.assertIsNone(sem("glTexImage2D")["redraw"])            # uploads are never redrawn
        # (and the uniform buffer a glBufferSubData of the frame uploads into)
        self.assertEqual([e for _, e in sem("glBindBuffer")["redraw_first_values"]],
                         ["GL_ARRAY_BUFFER", "GL_ELEMENT_ARRAY_BUFFER", "GL_UNIFORM_BUFFER"])

    def test_primitive_modes_of_draws(self):
        # (gl.xml's group PrimitiveType: which draws draw lines or points)
        self.assertEqual(sem("glDrawElements")["primitive_param"], 0)
        self.assertEqual(sem("glBegin")["primitive_param"], 0)
        self.assertEqual(sem("glMultiDrawElementsBaseVertex")["primitive_param"], 0)
        self.assertEqual(sem("glMultiModeDrawArraysIBM")["primitive_param"], -1)  # one mode per draw, an array
        self.assertEqual(sem("glCallList")["primitive_param"], -1)
        self.assertEqual(sem("glBeginTransformFeedback")["primitive_param"], -1)  # not a draw

    def test_state_writes_and_contexts(self):
        self.assertEqual((sem("glEnable")["state"], sem("glEnable")["state_key"]), ("enable", [0]))
        self.assertEqual((sem("glLightfv")["state"], sem("glLightfv")["state_key"]), ("lighting", [0, 1]))
        self.assertTrue(sem("glClear")["frame_only"] and sem("glDrawArrays")["frame_only"])
        self.assertFalse(sem("glTexImage2D")["frame_only"])
        self.assertEqual((sem("glTexImage2D")["writes"], sem("glTexImage2D")["writes_ns"]), ("bound", "texture"))
        self.assertEqual((sem("glNamedBufferData")["writes"], sem("glNamedBufferData")["writes_param"]), ("named", 0))
        self.assertEqual((sem("eglMakeCurrent")["context"], sem("eglMakeCurrent")["context_param"]), ("make_current", 1))
        self.assertEqual(sem("glXSwapBuffers")["context"], "swap")


class AnnotationErrors(unittest.TestCase):
    def run_with(self, edit):
        """Runs the generator on a copy of codegen/ whose annotations `edit` changed."""
        with tempfile.TemporaryDirectory() as tmp:
            subprocess.run(["cp", "-r", os.path.join(HERE, "..", "codegen"), tmp], check=True)
            subprocess.run(["cp", "-r", os.path.join(HERE, "..", "interceptor"), tmp], check=True)
            subprocess.run(["cp", "-r", os.path.join(HERE, "..", "slave"), tmp], check=True)
            edit(os.path.join(tmp, "codegen", "annotations"))
            return subprocess.run([sys.executable, os.path.join(tmp, "codegen", "glcast_codegen.py"), "--report"],
                                  capture_output=True, text=True)

    def test_handwritten_name_not_in_registry(self):
        def edit(d):
            with open(os.path.join(d, "handwritten.txt"), "a") as f:
                f.write("glNoSuchCommand\n")
        r = self.run_with(edit)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("glNoSuchCommand", r.stderr)

    def test_parameter_that_does_not_exist(self):
        def edit(d):
            with open(os.path.join(d, "commands.yaml"), "a") as f:
                f.write("")
            path = os.path.join(d, "commands.yaml")
            text = open(path).read().replace("  glNamedBufferData.data: {len: size}",
                                              "  glNamedBufferData.bogus: {len: size}")
            open(path, "w").write(text)
        r = self.run_with(edit)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("glNamedBufferData.bogus", r.stderr)

    def test_unknown_enum_in_pname_table(self):
        def edit(d):
            path = os.path.join(d, "pnames.yaml")
            text = open(path).read().replace("  light:\n    counts:\n", "  light:\n    counts:\n      GL_NOT_AN_ENUM: 4\n")
            open(path, "w").write(text)
        r = self.run_with(edit)
        self.assertNotEqual(r.returncode, 0, r.stdout[-500:])
        self.assertIn("GL_NOT_AN_ENUM", r.stderr)

    def edit_semantics(self, old, new):
        def edit(d):
            path = os.path.join(d, "semantics.yaml")
            text = open(path).read()
            self.assertIn(old, text)
            open(path, "w").write(text.replace(old, new))
        return self.run_with(edit)

    def test_twin_that_is_neither_declared_nor_refused(self):
        r = self.edit_semantics("  glBindFramebufferEXT: glBindFramebuffer ", "  ")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("glBindFramebufferEXT", r.stderr)
        self.assertIn("twins or not_twins", r.stderr)

    def edit_client_arrays(self, old, new):
        def edit(d):
            path = os.path.join(d, "client_arrays.yaml")
            text = open(path).read()
            self.assertIn(old, text)
            open(path, "w").write(text.replace(old, new))
        return self.run_with(edit)

    def test_deferred_pointer_without_its_arrays(self):
        r = self.edit_client_arrays("  glVertexPointer: [vertex]\n", "")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("deferred, not listed: ['glVertexPointer']", r.stderr)

    def test_client_array_query_that_is_no_enum(self):
        r = self.edit_client_arrays("stride: GL_NORMAL_ARRAY_STRIDE", "stride: GL_NORMAL_ARRAY_STRIDES")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("fixed.normal.stride: unknown enum GL_NORMAL_ARRAY_STRIDES", r.stderr)

    def test_list_parameter_that_does_not_exist(self):
        r = self.edit_semantics("new: {glNewList: [list, mode]}", "new: {glNewList: [list, how]}")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("'how'", r.stderr)

    def test_pattern_that_matches_nothing(self):
        r = self.edit_semantics("  link: {glLinkProgram: program}", "  link: {glLinkProgam: program}")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("glLinkProgam", r.stderr)

    def test_semantics_parameter_that_does_not_exist(self):
        r = self.edit_semantics("glBindFramebuffer: [target, framebuffer]", "glBindFramebuffer: [target, fb]")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("'fb'", r.stderr)

    def test_slave_handwritten_without_definition(self):
        def edit(d):
            path = os.path.join(d, "commands.yaml")
            text = open(path).read().replace("handwritten: [glGenLists,", "handwritten: [glFinish, glGenLists,")
            open(path, "w").write(text)
        r = self.run_with(edit)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("listed, not defined: ['glFinish']", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
