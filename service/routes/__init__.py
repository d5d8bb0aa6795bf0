"""HTTP routes; each module holds one APIRouter and stays thin:
schema -> domain object -> model/solver -> schema."""
