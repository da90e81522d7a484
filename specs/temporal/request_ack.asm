// A monitored request and its acknowledgement one step later. As in AsmetaSMV, a
// monitored function is read in the state where the step reads it: `req` belongs to the
// state the step starts from, so ag(req implies ax(ack)) holds. The INVAR restricts the
// environment: no request while `busy`.
// asmcheck: expect violated ctlSpec_ack_now
// (these properties are false on purpose: the examples show how each one is refuted;
// with the fairness of the .prop file beside the spec some of them hold)
asm request_ack

import StandardLibrary
import CTLLibrary
import LTLLibrary

signature:
	dynamic monitored req: Boolean
	dynamic controlled ack: Boolean
	dynamic controlled busy: Boolean

definitions:
	INVAR not (busy and req)

	CTLSPEC ctlSpec_ack_next: ag(req implies ax(ack))
	CTLSPEC ctlSpec_ack_now: ag(req implies ack)
	CTLSPEC ctlSpec_no_req_when_busy: ag(busy implies not req)
	LTLSPEC ltlSpec_ack_next: g(req implies x(ack))
	LTLSPEC ltlSpec_ack_after_req: g(ack implies y(req))

	main rule r_main =
		par
			ack := req
			busy := req
		endpar

default init s0:
	function ack = false
	function busy = false
